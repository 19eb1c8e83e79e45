// method.hpp - a registration method run by ppcr_bench: ppcr itself, or a peer (PCL, Open3D)
// when built with PPCR_BUILD_PEERS. Every method gets the same preprocessed clouds.
#pragma once

#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "ppcr/registration.hpp"
#include "ppcr/types.hpp"

namespace ppcr_bench {

/// What every method is told (the protocol's shared parameters, from the registration flags).
struct MethodSettings {
  ppcr::RegistrationOptions ppcr;   // ppcr's options (voxel filtering already done by the bench)
  double max_correspondence = 1.0;  // ICP / GICP max correspondence distance (= --radius)
  double ndt_resolution = 1.0;      // NDT cell size (= 2 x --radius by default)
  int max_iterations = 100;         // iteration cap for the peers (= --max-iterations)
  int threads = 1;
  // ppcr: one ppcr::Registration for every problem (set_target and align per problem: the loop
  // usage, whose buffers are reused), instead of ppcr::align per problem (the default).
  bool reuse_registration = false;
};

struct MethodResult {
  bool ok = false;
  std::string message;  // why not ok
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  int iterations = 0;
  std::string stop_reason;
  bool converged = false;
  std::vector<ppcr::IterationRecord> history;  // ppcr with set_trace(): one row per iteration
  // ppcr's measures of the result (RegistrationResult); NaN, -1 or empty for the peers.
  double fitness = std::numeric_limits<double>::quiet_NaN();
  double inlier_rmse = std::numeric_limits<double>::quiet_NaN();
  double overlap = std::numeric_limits<double>::quiet_NaN();
  double scale = std::numeric_limits<double>::quiet_NaN();
  double target_surface_noise = std::numeric_limits<double>::quiet_NaN();
  double target_spacing = std::numeric_limits<double>::quiet_NaN();
  double close_fraction = std::numeric_limits<double>::quiet_NaN();
  double radius = std::numeric_limits<double>::quiet_NaN();  // the radius used
  int degenerate_directions = -1;
  std::string quality;
  double quality_ms = std::numeric_limits<double>::quiet_NaN();
  // ppcr's pose covariance (RegistrationResult::covariance); NaN for the peers.
  Eigen::Matrix<double, 6, 6> covariance =
      Eigen::Matrix<double, 6, 6>::Constant(std::numeric_limits<double>::quiet_NaN());
};

class Method {
 public:
  virtual ~Method() = default;
  virtual std::string name() const = 0;
  /// Registers source onto target from identity. Timed by the caller, whole call.
  virtual MethodResult run(const ppcr::PointCloud& source, const ppcr::PointCloud& target) = 0;
  /// Methods that can trace their iterations (ppcr) record the next runs' history. Others
  /// ignore it.
  virtual void set_trace(bool trace) { (void)trace; }
};

/// Method names this build offers ("ppcr" and "ppcr-reuse" always; "pcl-icp", ... with peers).
std::vector<std::string> available_methods();

/// Creates a method by name, or nullptr if unknown / not built.
std::unique_ptr<Method> make_method(const std::string& name, const MethodSettings& settings);

}  // namespace ppcr_bench
