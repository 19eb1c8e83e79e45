// method_ppcr.cpp - ppcr as a benchmark method, and the method registry.
#include <memory>
#include <utility>

#include "bench/method.hpp"

#ifdef PPCR_HAVE_PEERS
#include "bench/peers.hpp"
#endif

namespace ppcr_bench {
namespace {

class PpcrMethod : public Method {
 public:
  PpcrMethod(std::string name, const ppcr::RegistrationOptions& options, bool reuse)
      : name_(std::move(name)), options_(options), reuse_(reuse) {}
  std::string name() const override { return name_; }
  void set_trace(bool trace) override { trace_ = trace; }
  MethodResult run(const ppcr::PointCloud& source, const ppcr::PointCloud& target) override {
    ppcr::RegistrationOptions options = options_;
    options.record_history = trace_;
    MethodResult out;
    ppcr::RegistrationResult r;
    if (reuse_) {
      // The loop usage: one Registration, its buffers reused from problem to problem (made
      // again only if the trace setting changes).
      if (!registration_ || registration_->options().record_history != trace_) {
        registration_ = std::make_unique<ppcr::Registration>(options);
      }
      const ppcr::Status s = registration_->set_target(target);
      if (!s.ok()) {  // as ppcr::align reports a refused target
        out.message = s.message();
        out.stop_reason = ppcr::to_string(ppcr::StopReason::kInvalidInput);
        return out;
      }
      r = registration_->align(source, Eigen::Isometry3d::Identity());
    } else {
      r = ppcr::align(source, target, options, Eigen::Isometry3d::Identity());
    }
    out.ok = r.status.ok();
    out.message = r.status.message();
    out.T_target_source = r.T_target_source;
    out.iterations = r.iterations;
    out.stop_reason = ppcr::to_string(r.stop_reason);
    out.converged = r.converged();
    out.history = r.history;
    out.fitness = r.fitness;
    out.inlier_rmse = r.inlier_rmse;
    out.overlap = r.overlap;
    out.scale = r.scale;
    out.target_surface_noise = r.target_surface_noise;
    out.target_spacing = r.target_spacing;
    out.close_fraction = r.close_fraction;
    out.radius = r.radius;
    out.quality = ppcr::to_string(r.quality);
    out.degenerate_directions = r.degenerate_directions;
    out.quality_ms = r.quality_ms;
    out.covariance = r.covariance;
    return out;
  }

 private:
  std::string name_;
  ppcr::RegistrationOptions options_;
  bool reuse_;
  std::unique_ptr<ppcr::Registration> registration_;  // with reuse_
  bool trace_ = false;
};

}  // namespace

std::vector<std::string> available_methods() {
  std::vector<std::string> names = {"ppcr", "ppcr-reuse"};
#ifdef PPCR_HAVE_PEERS
  for (const std::string& n : peer_methods()) names.push_back(n);
#endif
  return names;
}

std::unique_ptr<Method> make_method(const std::string& name, const MethodSettings& settings) {
  // ppcr-reuse: ppcr in the loop usage whatever reuse_registration says, so that one run can
  // time it against the one-shot calls (--methods ppcr,ppcr-reuse); the results are the same.
  if (name == "ppcr" || name == "ppcr-reuse") {
    ppcr::RegistrationOptions options = settings.ppcr;
    options.source_voxel = options.target_voxel = 0.0;  // the bench filters once, for everyone
    options.record_history = false;
    return std::make_unique<PpcrMethod>(name, options,
                                        settings.reuse_registration || name == "ppcr-reuse");
  }
#ifdef PPCR_HAVE_PEERS
  return make_peer(name, settings);
#else
  return nullptr;
#endif
}

}  // namespace ppcr_bench
