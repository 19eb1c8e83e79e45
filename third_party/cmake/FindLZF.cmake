# FindLZF.cmake -- our glue for liblzf (Debian/Ubuntu: liblzf-dev), used by ppcr_io to read PCD
# DATA binary_compressed.
#
# Debian's liblzf-dev ships a CMake package (target liblzf::liblzf) and puts the header in
# /usr/include/liblzf/lzf.h; other installs put lzf.h directly in an include folder. We try the
# package first (CONFIG mode), then find_path/find_library. Either way the result is the imported
# target LZF::LZF, whose include folder holds lzf.h.
#
# Hints: LZF_ROOT, or LZF_INCLUDE_DIR (folder holding lzf.h) and LZF_LIBRARY.

if(TARGET LZF::LZF)
  set(LZF_FOUND TRUE)
  return()
endif()

find_package(liblzf CONFIG QUIET)
if(liblzf_FOUND AND TARGET liblzf::liblzf)
  add_library(LZF::LZF INTERFACE IMPORTED)
  set_target_properties(LZF::LZF PROPERTIES INTERFACE_LINK_LIBRARIES liblzf::liblzf)
  set(LZF_FOUND TRUE)
  set(LZF_VERSION ${liblzf_VERSION})
  if(NOT LZF_FIND_QUIETLY)
    message(STATUS "Found LZF (CMake package liblzf) ${liblzf_VERSION}")
  endif()
  return()
endif()

find_path(LZF_INCLUDE_DIR NAMES lzf.h
          HINTS ${LZF_ROOT} ENV LZF_ROOT
          PATH_SUFFIXES include include/liblzf liblzf)
find_library(LZF_LIBRARY NAMES lzf liblzf
             HINTS ${LZF_ROOT} ENV LZF_ROOT
             PATH_SUFFIXES lib lib64)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(LZF REQUIRED_VARS LZF_LIBRARY LZF_INCLUDE_DIR)

if(LZF_FOUND AND NOT TARGET LZF::LZF)
  add_library(LZF::LZF UNKNOWN IMPORTED)
  set_target_properties(LZF::LZF PROPERTIES
    IMPORTED_LOCATION "${LZF_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${LZF_INCLUDE_DIR}")
endif()
mark_as_advanced(LZF_INCLUDE_DIR LZF_LIBRARY)
