# peers.cmake - registration peers for ppcr_bench (included by tools/bench/CMakeLists.txt when
# PPCR_BUILD_PEERS is ON): PCL's ICP, GICP and NDT (required; Debian: libpcl-dev) and Open3D's
# ICP, point-to-plane ICP and GICP (when found; Debian: libopen3d-dev). Only ppcr_bench links
# them: the core library and the other tools never see PCL or Open3D.

# PCL's config looks for VTK as an optional dependency of pcl_2d (pulled in by registration), and
# Debian's VTK 9.1 config then fails on a missing MPI::MPI_C target; registration needs no VTK, so
# keep that search off (this directory scope only).
set(CMAKE_DISABLE_FIND_PACKAGE_VTK ON)
find_package(PCL 1.10 REQUIRED QUIET COMPONENTS common kdtree search registration)
unset(CMAKE_DISABLE_FIND_PACKAGE_VTK)
message(STATUS "ppcr_bench peers: PCL ${PCL_VERSION}")

target_sources(ppcr_bench PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/peers.cpp
  ${CMAKE_CURRENT_LIST_DIR}/peers_pcl.cpp)
# SYSTEM: PCL's (and its dependencies') headers are not ours to keep warning-free.
target_include_directories(ppcr_bench SYSTEM PRIVATE ${PCL_INCLUDE_DIRS})
target_link_libraries(ppcr_bench PRIVATE ${PCL_LIBRARIES})
target_compile_definitions(ppcr_bench PRIVATE PPCR_HAVE_PEERS)
# GCC 12 reports -Warray-bounds inside Eigen's float Umeyama (PCL's SVD estimation for ICP) once
# inlined into our translation unit, past the SYSTEM marking; a false positive in headers.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/peers_pcl.cpp
    PROPERTIES COMPILE_OPTIONS -Wno-array-bounds)
endif()

option(PPCR_PEERS_OPEN3D "Add Open3D's methods to ppcr_bench when Open3D is found" ON)
if(PPCR_PEERS_OPEN3D)
  find_package(Open3D CONFIG QUIET)
  find_package(OpenMP COMPONENTS CXX QUIET)  # the Open3D peers set OpenMP's thread count
  if(Open3D_FOUND AND OpenMP_CXX_FOUND)
    message(STATUS "ppcr_bench peers: Open3D ${Open3D_VERSION}")
    target_sources(ppcr_bench PRIVATE ${CMAKE_CURRENT_LIST_DIR}/peers_open3d.cpp)
    # Open3D::Open3D is an imported target, so its include directory is already SYSTEM.
    target_link_libraries(ppcr_bench PRIVATE Open3D::Open3D OpenMP::OpenMP_CXX)
    target_compile_definitions(ppcr_bench PRIVATE PPCR_HAVE_OPEN3D)
  else()
    message(STATUS "ppcr_bench peers: Open3D (or OpenMP) not found, Open3D methods left out")
  endif()
endif()
