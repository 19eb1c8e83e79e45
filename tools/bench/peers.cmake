# peers.cmake - registration peers for ppcr_bench (included by tools/bench/CMakeLists.txt when
# PPCR_BUILD_PEERS is ON): PCL's ICP, GICP and NDT (required; Debian: libpcl-dev) and Open3D's
# ICP, point-to-plane ICP and GICP (when found; Debian: libopen3d-dev), found by
# third_party/cmake/FindPeers.cmake. ppcr_bench and ppcr_odometry link them: the core library
# never sees PCL or Open3D.

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

if(PPCR_PEERS_WITH_OPEN3D)
  target_sources(ppcr_bench PRIVATE ${CMAKE_CURRENT_LIST_DIR}/peers_open3d.cpp)
  # Open3D::Open3D is an imported target, so its include directory is already SYSTEM.
  target_link_libraries(ppcr_bench PRIVATE Open3D::Open3D OpenMP::OpenMP_CXX)
  target_compile_definitions(ppcr_bench PRIVATE PPCR_HAVE_OPEN3D)
endif()
