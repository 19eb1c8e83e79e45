// ppcr_registrar.cpp - ppcr as the sequence's registration: one Registration, set_target per
// target, align from the constant-velocity guess.
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
    // The target's filtering, index and normals are made again for each target: the public API
    // cannot hand over the structures align() built for the previous source.
    return registration_.set_target(target);
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
