# Findnanoflann.cmake -- our glue for nanoflann (header-only).
#
# Debian's libnanoflann-dev 1.4.3 ships a CMake package in /usr/share/nanoflann/cmake, older
# releases and plain header copies ship none. We try the package first (CONFIG mode), then fall
# back to locating nanoflann.hpp. Either way the result is the imported target nanoflann::nanoflann.
#
# Hints: nanoflann_ROOT or NANOFLANN_INCLUDE_DIR (a folder holding nanoflann.hpp).

if(TARGET nanoflann::nanoflann)
  set(nanoflann_FOUND TRUE)
  return()
endif()

find_package(nanoflann CONFIG QUIET)
if(nanoflann_FOUND AND TARGET nanoflann::nanoflann)
  if(NOT nanoflann_FIND_QUIETLY)
    message(STATUS "Found nanoflann (CMake package) ${nanoflann_VERSION}")
  endif()
  return()
endif()

find_path(NANOFLANN_INCLUDE_DIR NAMES nanoflann.hpp
          HINTS ${nanoflann_ROOT} ENV nanoflann_ROOT
          PATH_SUFFIXES include)

if(NANOFLANN_INCLUDE_DIR AND EXISTS "${NANOFLANN_INCLUDE_DIR}/nanoflann.hpp")
  file(STRINGS "${NANOFLANN_INCLUDE_DIR}/nanoflann.hpp" _nf_ver
       REGEX "^#define NANOFLANN_VERSION 0x[0-9a-fA-F]+")
  if(_nf_ver MATCHES "0x([0-9a-fA-F])([0-9a-fA-F])([0-9a-fA-F])")
    set(nanoflann_VERSION "${CMAKE_MATCH_1}.${CMAKE_MATCH_2}.${CMAKE_MATCH_3}")
  endif()
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(nanoflann
  REQUIRED_VARS NANOFLANN_INCLUDE_DIR
  VERSION_VAR nanoflann_VERSION)

if(nanoflann_FOUND AND NOT TARGET nanoflann::nanoflann)
  add_library(nanoflann::nanoflann INTERFACE IMPORTED)
  set_target_properties(nanoflann::nanoflann PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${NANOFLANN_INCLUDE_DIR}")
endif()
mark_as_advanced(NANOFLANN_INCLUDE_DIR)
