// peer_registrar.cpp - the bench's peer methods (tools/bench/peers.hpp) as the sequence's
// registration. A peer registers from identity, so the source is first moved by the guess and
// the guess composed back onto the peer's answer: T = T_peer * T_guess. As in the bench, a peer
// gets the clouds voxel-filtered by --source-voxel and --target-voxel (ppcr filters inside).
#include <Eigen/SVD>
#include <memory>

#include "bench/peers.hpp"
#include "odometry/pair_registrar.hpp"
#include "ppcr/voxel.hpp"

namespace ppcr_odometry {
namespace {

class PeerRegistrar : public PairRegistrar {
 public:
  PeerRegistrar(std::unique_ptr<ppcr_bench::Method> method, double source_voxel,
                double target_voxel)
      : method_(std::move(method)), source_voxel_(source_voxel), target_voxel_(target_voxel) {}
  std::string name() const override { return method_->name(); }
  ppcr::Status set_target(const ppcr::PointCloud& target) override {
    // The peer builds its structures inside run(), timed with it.
    return filter(target, target_voxel_, &target_);
  }
  PairOutcome align(const ppcr::PointCloud& source, const Eigen::Isometry3d& T_guess) override {
    PairOutcome out;
    out.result.status = filter(source, source_voxel_, &moved_);
    if (!out.result.status.ok()) return out;
    for (Eigen::Vector3d& p : moved_) p = T_guess * p;
    const ppcr_bench::MethodResult r = method_->run(moved_, target_);
    if (!r.ok) out.result.status = ppcr::Status(ppcr::StatusCode::kInvalidArgument, r.message);
    out.result.T_target_source = r.T_target_source * T_guess;
    // PCL works in float: its rotation is orthonormal to ~1e-7 only, and chaining hundreds of
    // them would drift; use the nearest rotation.
    out.result.T_target_source.linear() = nearest_rotation(out.result.T_target_source.linear());
    out.result.iterations = r.iterations;
    out.stop_reason = r.stop_reason;
    return out;
  }

 private:
  static Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& M) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    return svd.matrixU() * svd.matrixV().transpose();
  }
  static ppcr::Status filter(const ppcr::PointCloud& cloud, double leaf, ppcr::PointCloud* out) {
    if (leaf > 0.0) return ppcr::voxel_downsample(cloud, leaf, out);
    *out = cloud;
    return ppcr::Status::Ok();
  }

  std::unique_ptr<ppcr_bench::Method> method_;
  double source_voxel_, target_voxel_;
  ppcr::PointCloud target_, moved_;
};

}  // namespace

std::vector<std::string> registrar_names() {
  std::vector<std::string> names{"ppcr"};
  for (const std::string& peer : ppcr_bench::peer_methods()) names.push_back(peer);
  return names;
}

std::unique_ptr<PairRegistrar> make_peer_registrar(const std::string& name,
                                                   const ppcr::RegistrationOptions& options) {
  ppcr_bench::MethodSettings settings;
  settings.ppcr = options;
  settings.max_correspondence = options.radius;
  settings.ndt_resolution = 2.0 * options.radius;
  settings.max_iterations = options.max_iterations;
  settings.threads = options.num_threads;
  std::unique_ptr<ppcr_bench::Method> method = ppcr_bench::make_peer(name, settings);
  if (!method) return nullptr;
  return std::make_unique<PeerRegistrar>(std::move(method), options.source_voxel,
                                         options.target_voxel);
}

}  // namespace ppcr_odometry
