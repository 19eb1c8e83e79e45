// pair_registrar.hpp - registers each scan of a sequence onto its target (the previous scan or
// the local map): ppcr, or a peer method of the bench (PCL, Open3D) when built with
// PPCR_BUILD_PEERS, behind one interface so that the same sequence runs through each.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "ppcr/options.hpp"
#include "ppcr/result.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr_odometry {

struct PairOutcome {
  /// ppcr's whole result. A peer fills status (not ok: it refused its input or failed),
  /// T_target_source and iterations only.
  ppcr::RegistrationResult result;
  bool has_measures = false;  // result's fitness, inlier_rmse, quality, spacing are ppcr's
  std::string stop_reason;
};

class PairRegistrar {
 public:
  virtual ~PairRegistrar() = default;
  virtual std::string name() const = 0;
  /// The target of the next align() calls (its prepared structures are kept until the next
  /// set_target). The cloud must outlive those calls.
  virtual ppcr::Status set_target(const ppcr::PointCloud& target) = 0;
  /// The same, when target is the source of the last align() (scan-to-scan): ppcr takes over
  /// the structures align() built for it; a peer prepares it again.
  virtual ppcr::Status set_target_to_source(const ppcr::PointCloud& target) {
    return set_target(target);
  }
  /// Registers source onto the target from T_guess (source into the target's frame).
  virtual PairOutcome align(const ppcr::PointCloud& source, const Eigen::Isometry3d& T_guess) = 0;
};

/// ppcr: one ppcr::Registration for the whole sequence (its buffers reused from scan to scan).
std::unique_ptr<PairRegistrar> make_ppcr_registrar(const ppcr::RegistrationOptions& options);

/// The methods --method accepts in this build: "ppcr", then the bench's peers when built with
/// them.
std::vector<std::string> registrar_names();

/// A peer by name, with the bench's shared settings (max correspondence distance = radius, NDT
/// cell = 2 x radius, the iteration cap and threads of options); nullptr for an unknown name.
std::unique_ptr<PairRegistrar> make_peer_registrar(const std::string& name,
                                                   const ppcr::RegistrationOptions& options);

}  // namespace ppcr_odometry
