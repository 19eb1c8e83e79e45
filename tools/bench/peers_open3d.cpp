// peers_open3d.cpp - Open3D's (legacy pipelines::registration) methods as ppcr_bench peers:
//   o3d-icp        RegistrationICP, TransformationEstimationPointToPoint (no scaling)
//   o3d-icp-plane  RegistrationICP, TransformationEstimationPointToPlane (L2 loss); target
//                  normals from its 20 nearest neighbours (EstimateNormals, KNN 20)
//   o3d-gicp       RegistrationGeneralizedICP (epsilon 1e-3, L2 loss, Open3D defaults); per-point
//                  covariances of source and target from their 20 nearest neighbours
//                  (EstimateCovariances, KNN 20, as PCL's GICP)
// The clouds are converted from ppcr::PointCloud inside run(), and normals / covariances are
// estimated there too, so all of it is part of the timed call.
//
// Shared settings: max correspondence distance = settings.max_correspondence (--radius), iteration
// cap = settings.max_iterations (--max-iterations; Open3D's default is 30). Convergence: Open3D's
// defaults, i.e. stop when both the fitness (inlier fraction) and the inlier RMSE change by less
// than 1e-6 between iterations (absolute changes; the RMSE is in cloud units).
//
// Threads: Open3D parallelises correspondence search, normal / covariance estimation and the
// normal equations with OpenMP; run() sets OpenMP's thread count to settings.threads (--threads)
// before calling it (the bench runs one method per process, so nothing else shares that setting).
//
// Iterations: Open3D 0.16 reports neither an iteration count nor why it stopped, so each method's
// transformation estimation is wrapped in a subclass that counts ComputeTransformation calls, one
// per ICP iteration. Stop reason: "max_iterations" when the count reached the cap (this includes
// a convergence on the very last allowed iteration), "no_correspondences" when the final fitness
// is 0, else "fitness_rmse" (converged).
#include <omp.h>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/GeneralizedICP.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/pipelines/registration/TransformationEstimation.h>

#include <Eigen/Core>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "bench/peers.hpp"

namespace ppcr_bench {
namespace {

namespace o3d_geometry = open3d::geometry;
namespace o3d_registration = open3d::pipelines::registration;

// Neighbours for target normals (o3d-icp-plane) and per-point covariances (o3d-gicp).
constexpr int kNeighbours = 20;

// An Open3D transformation estimation that counts its ComputeTransformation calls: RegistrationICP
// calls it once per iteration.
template <typename Estimation>
class Counting : public Estimation {
 public:
  using Estimation::Estimation;
  Eigen::Matrix4d ComputeTransformation(
      const o3d_geometry::PointCloud& source, const o3d_geometry::PointCloud& target,
      const o3d_registration::CorrespondenceSet& corres) const override {
    ++calls_;
    return Estimation::ComputeTransformation(source, target, corres);
  }
  int calls() const { return calls_; }

 private:
  mutable int calls_ = 0;
};

enum class Variant { kPointToPoint, kPointToPlane, kGeneralized };

class Open3dMethod : public Method {
 public:
  Open3dMethod(std::string name, Variant variant, const MethodSettings& settings)
      : name_(std::move(name)), variant_(variant), settings_(settings) {}
  std::string name() const override { return name_; }

  MethodResult run(const ppcr::PointCloud& source, const ppcr::PointCloud& target) override {
    omp_set_num_threads(settings_.threads);
    try {
      o3d_geometry::PointCloud src(source);
      o3d_geometry::PointCloud tgt(target);
      const o3d_registration::ICPConvergenceCriteria criteria(1e-6, 1e-6, settings_.max_iterations);
      const double distance = settings_.max_correspondence;
      const Eigen::Matrix4d init = Eigen::Matrix4d::Identity();
      o3d_registration::RegistrationResult r;
      int iterations = 0;
      switch (variant_) {
        case Variant::kPointToPoint: {
          const Counting<o3d_registration::TransformationEstimationPointToPoint> estimation(false);
          r = o3d_registration::RegistrationICP(src, tgt, distance, init, estimation, criteria);
          iterations = estimation.calls();
          break;
        }
        case Variant::kPointToPlane: {
          tgt.EstimateNormals(o3d_geometry::KDTreeSearchParamKNN(kNeighbours));
          const Counting<o3d_registration::TransformationEstimationPointToPlane> estimation;
          r = o3d_registration::RegistrationICP(src, tgt, distance, init, estimation, criteria);
          iterations = estimation.calls();
          break;
        }
        case Variant::kGeneralized: {
          src.EstimateCovariances(o3d_geometry::KDTreeSearchParamKNN(kNeighbours));
          tgt.EstimateCovariances(o3d_geometry::KDTreeSearchParamKNN(kNeighbours));
          const Counting<o3d_registration::TransformationEstimationForGeneralizedICP> estimation;
          r = o3d_registration::RegistrationGeneralizedICP(src, tgt, distance, init, estimation,
                                                           criteria);
          iterations = estimation.calls();
          break;
        }
      }
      MethodResult out;
      out.ok = true;
      const Eigen::Matrix4d T = r.transformation_;
      out.T_target_source.linear() = T.topLeftCorner<3, 3>();
      out.T_target_source.translation() = T.topRightCorner<3, 1>();
      out.iterations = iterations;
      if (iterations >= settings_.max_iterations) {
        out.stop_reason = "max_iterations";
      } else if (r.fitness_ <= 0.0) {
        out.stop_reason = "no_correspondences";
      } else {
        out.stop_reason = "fitness_rmse";
        out.converged = true;
      }
      return out;
    } catch (const std::exception& e) {  // Open3D's LogError throws std::runtime_error
      MethodResult out;
      out.ok = false;
      out.message = e.what();
      out.stop_reason = "exception";
      return out;
    }
  }

 private:
  std::string name_;
  Variant variant_;
  MethodSettings settings_;
};

}  // namespace

std::vector<std::string> open3d_methods() { return {"o3d-icp", "o3d-icp-plane", "o3d-gicp"}; }

std::unique_ptr<Method> make_open3d_method(const std::string& name,
                                           const MethodSettings& settings) {
  if (name == "o3d-icp") {
    return std::make_unique<Open3dMethod>(name, Variant::kPointToPoint, settings);
  }
  if (name == "o3d-icp-plane") {
    return std::make_unique<Open3dMethod>(name, Variant::kPointToPlane, settings);
  }
  if (name == "o3d-gicp") {
    return std::make_unique<Open3dMethod>(name, Variant::kGeneralized, settings);
  }
  return nullptr;
}

}  // namespace ppcr_bench
