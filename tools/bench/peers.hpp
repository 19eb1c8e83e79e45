// peers.hpp - registration methods of other libraries ("peers") offered by ppcr_bench when it is
// built with PPCR_BUILD_PEERS: PCL always, Open3D when found (PPCR_HAVE_OPEN3D). Each peer gets
// the clouds ppcr gets (already voxel-filtered by the bench) and converts them to its library's
// cloud type inside Method::run, so the conversion is part of the timed call.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bench/method.hpp"

namespace ppcr_bench {

/// Every peer method name this build offers ("pcl-icp", "pcl-gicp", "pcl-ndt", "o3d-...").
std::vector<std::string> peer_methods();

/// Creates a peer by name, or nullptr for a name that is not a peer of this build.
std::unique_ptr<Method> make_peer(const std::string& name, const MethodSettings& settings);

/// PCL's methods (peers_pcl.cpp).
std::vector<std::string> pcl_methods();
std::unique_ptr<Method> make_pcl_method(const std::string& name, const MethodSettings& settings);

#ifdef PPCR_HAVE_OPEN3D
/// Open3D's methods (peers_open3d.cpp).
std::vector<std::string> open3d_methods();
std::unique_ptr<Method> make_open3d_method(const std::string& name, const MethodSettings& settings);
#endif

}  // namespace ppcr_bench
