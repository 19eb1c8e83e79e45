// ppcr_registrar.cpp - ppcr as the sequence's registration: one Registration, a target per scan
// (scan-to-scan: the previous source, as align() prepared it), align from the constant-velocity
// guess.
#include <memory>

#include "odometry/pair_registrar.hpp"
#include "ppcr/registration.hpp"

namespace ppcr_odometry {
namespace {

class PpcrRegistrar : public PairRegistrar {
 public:
  explicit PpcrRegistrar(const ppcr::RegistrationOptions& options) : registration_(options) {}
  std::string name() const override { return "ppcr"; }
  ppcr::Status set_target(const ppcr::PointCloud& target) override {
    return registration_.set_target(target);
  }
  ppcr::Status set_target_to_source(const ppcr::PointCloud& target) override {
    // The source's filtering, index and normal fits serve as the target's when it was filtered
    // alike (the same result: Registration::set_target_to_source()).
    const ppcr::RegistrationOptions& o = registration_.options();
    if (o.source_voxel != o.target_voxel) return registration_.set_target(target);
    return registration_.set_target_to_source();
  }
  PairOutcome align(const ppcr::PointCloud& source, const Eigen::Isometry3d& T_guess) override {
    PairOutcome out;
    out.result = registration_.align(source, T_guess);
    out.has_measures = true;
    out.stop_reason = ppcr::to_string(out.result.stop_reason);
    return out;
  }

 private:
  ppcr::Registration registration_;
};

}  // namespace

std::unique_ptr<PairRegistrar> make_ppcr_registrar(const ppcr::RegistrationOptions& options) {
  return std::make_unique<PpcrRegistrar>(options);
}

}  // namespace ppcr_odometry
