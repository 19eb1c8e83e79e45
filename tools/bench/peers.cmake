# peers.cmake - registration peers (included by tools/bench/CMakeLists.txt when PPCR_BUILD_PEERS is
# ON): PCL's ICP, GICP and NDT (required; Debian: libpcl-dev) and Open3D's ICP, point-to-plane ICP
# and GICP (when found; Debian: libopen3d-dev), found by third_party/cmake/find_peers.cmake. One
# library, ppcr_bench_peers, that ppcr_bench and ppcr_odometry link: the core library never sees
# PCL or Open3D.

add_library(ppcr_bench_peers STATIC
  ${CMAKE_CURRENT_LIST_DIR}/peers.cpp
  ${CMAKE_CURRENT_LIST_DIR}/peers_pcl.cpp)
# SYSTEM: PCL's (and its dependencies') headers are not ours to keep warning-free.
target_include_directories(ppcr_bench_peers SYSTEM PRIVATE ${PCL_INCLUDE_DIRS})
target_link_libraries(ppcr_bench_peers PUBLIC ppcr_tool_common ${PCL_LIBRARIES}
  PRIVATE ppcr_warnings)
# Who links the peers sees PPCR_HAVE_PEERS (and PPCR_HAVE_OPEN3D: peers.hpp declares by it).
target_compile_definitions(ppcr_bench_peers PUBLIC PPCR_HAVE_PEERS)
# GCC 12 reports -Warray-bounds inside Eigen's float Umeyama (PCL's SVD estimation for ICP) once
# inlined into our translation unit, past the SYSTEM marking; a false positive in headers.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/peers_pcl.cpp
    PROPERTIES COMPILE_OPTIONS -Wno-array-bounds)
endif()

if(PPCR_PEERS_WITH_OPEN3D)
  target_sources(ppcr_bench_peers PRIVATE ${CMAKE_CURRENT_LIST_DIR}/peers_open3d.cpp)
  # Open3D::Open3D is an imported target, so its include directory is already SYSTEM.
  target_link_libraries(ppcr_bench_peers PUBLIC Open3D::Open3D OpenMP::OpenMP_CXX)
  target_compile_definitions(ppcr_bench_peers PUBLIC PPCR_HAVE_OPEN3D)
endif()

target_link_libraries(ppcr_bench PRIVATE ppcr_bench_peers)
