// peers.cpp - the peer registry: PCL's methods, then Open3D's when built with them.
#include "bench/peers.hpp"

namespace ppcr_bench {

std::vector<std::string> peer_methods() {
  std::vector<std::string> names = pcl_methods();
#ifdef PPCR_HAVE_OPEN3D
  for (const std::string& n : open3d_methods()) names.push_back(n);
#endif
  return names;
}

std::unique_ptr<Method> make_peer(const std::string& name, const MethodSettings& settings) {
  std::unique_ptr<Method> method = make_pcl_method(name, settings);
#ifdef PPCR_HAVE_OPEN3D
  if (!method) method = make_open3d_method(name, settings);
#endif
  return method;
}

}  // namespace ppcr_bench
