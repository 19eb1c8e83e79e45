# find_peers.cmake - finds the registration peers of ppcr_bench and ppcr_odometry
# (PPCR_BUILD_PEERS; include()d, not a find module):
# PCL's ICP, GICP and NDT (required; Debian: libpcl-dev) and Open3D's ICP, point-to-plane ICP and
# GICP (when found, with OpenMP; Debian: libopen3d-dev). Included from the top-level CMakeLists so
# that their imported targets are visible to every directory below it: the tools that compile the
# peers and the tests that link those tools' libraries. The core library never sees them.
# Sets PPCR_PEERS_WITH_OPEN3D.

# PCL's config looks for VTK as an optional dependency of pcl_2d (pulled in by registration), and
# Debian's VTK 9.1 config then fails on a missing MPI::MPI_C target; registration needs no VTK, so
# keep that search off.
set(CMAKE_DISABLE_FIND_PACKAGE_VTK ON)
find_package(PCL 1.10 REQUIRED QUIET COMPONENTS common kdtree search registration)
unset(CMAKE_DISABLE_FIND_PACKAGE_VTK)
message(STATUS "ppcr peers: PCL ${PCL_VERSION}")

option(PPCR_PEERS_OPEN3D "Add Open3D's methods to the peers when Open3D is found" ON)
set(PPCR_PEERS_WITH_OPEN3D OFF)
if(PPCR_PEERS_OPEN3D)
  find_package(Open3D CONFIG QUIET)
  find_package(OpenMP COMPONENTS CXX QUIET)  # the Open3D peers set OpenMP's thread count
  if(Open3D_FOUND AND OpenMP_CXX_FOUND)
    set(PPCR_PEERS_WITH_OPEN3D ON)
    message(STATUS "ppcr peers: Open3D ${Open3D_VERSION}")
  else()
    message(STATUS "ppcr peers: Open3D (or OpenMP) not found, Open3D methods left out")
  endif()
endif()
