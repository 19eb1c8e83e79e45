// no_peers.cpp - a build without PPCR_BUILD_PEERS: ppcr is the only method.
#include "odometry/pair_registrar.hpp"

namespace ppcr_odometry {

std::vector<std::string> registrar_names() { return {"ppcr"}; }

std::unique_ptr<PairRegistrar> make_peer_registrar(const std::string& name,
                                                   const ppcr::RegistrationOptions& options) {
  (void)name;
  (void)options;
  return nullptr;
}

}  // namespace ppcr_odometry
