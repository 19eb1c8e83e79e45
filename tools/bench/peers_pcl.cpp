// peers_pcl.cpp - PCL's registration methods as ppcr_bench peers:
//   pcl-icp   pcl::IterativeClosestPoint (point-to-point, SVD)
//   pcl-gicp  pcl::GeneralizedIterativeClosestPoint (plane-to-plane, BFGS)
//   pcl-ndt   pcl::NormalDistributionsTransform (Magnusson's P2D NDT, More-Thuente line search)
// All run in float (pcl::PointXYZ, PCL's default Scalar); the clouds are converted from
// ppcr::PointCloud inside run(), so the conversion (and every search structure PCL builds:
// kd-trees, GICP covariances, the NDT voxel grid) is part of the timed call.
//
// Shared settings: max correspondence distance = settings.max_correspondence (--radius), iteration
// cap = settings.max_iterations (--max-iterations). NDT's cell size = settings.ndt_resolution
// (2 x --radius). PCL 1.13's ICP, GICP and NDT are single-threaded, so settings.threads has
// nothing to pin: these classes have no OpenMP, and PCL's kd-tree asks FLANN for one core per
// query (FLANN still opens a one-thread OpenMP region per query, an overhead in PCL's times).
//
// Convergence (a PCL default unless a reason is given):
//   pcl-icp:  stops when the relative change of the correspondences' MSE is below 1e-5, when it
//             changes by less than 1e-12 in absolute terms (PCL default), or on an exactly zero
//             step (PCL's default transformation epsilon 0). Reason for the 1e-5: ICP's default
//             (-DBL_MAX) disables the relative test, leaving the absolute 1e-12 (units^2), which
//             depends on the cloud's unit: on a lidar scan (MSE ~ 0.1 m^2) it would never fire.
//             1e-5 is the relative threshold PCL's DefaultConvergenceCriteria itself defaults to.
//   pcl-gicp: PCL's defaults with every length in them scaled by the radius r (they are metres
//             tuned for metre-scale scenes, r = 1, where they are unchanged): stops when no
//             translation entry of the transform changes by more than 5e-4 r and no rotation
//             matrix entry by more than 2e-3 (default); each BFGS solve stops when the cost's
//             gradient is below 1e-2 r (translation) and 1e-2 r^2 (rotation; the rotation gradient
//             carries a lever arm), or after 20 iterations (default). Reason: with the unscaled
//             gradient tolerances, BFGS stops at once on the bunny (r = 0.02 m), and GICP
//             "converges" after 2-5 steps 5-12 degrees off (0 % success on the first problems;
//             scaled: 100 %). Covariances from the 20 nearest neighbours (default).
//   pcl-ndt:  stops when the last step moves by under 1e-3 x radius (PCL's transformation epsilon
//             is on the squared translation: (1e-3 r)^2) AND rotates by under 1e-3 rad. Reason:
//             PCL's default (squared translation <= 0.1 units^2, no rotation test) stops a
//             bunny (15 cm) after the first step whatever its rotation. Step size 0.1 (PCL
//             default: the More-Thuente line search's largest step on the 6-vector
//             [translation, Euler angles]; the search shortens it), outlier ratio 0.55 (default).
//
// Iterations: PCL's own counter (Registration::nr_iterations_, read through a subclass).
// converged = stopped by a convergence test, not by the iteration cap or a failure.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

#include <cmath>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "bench/peers.hpp"

namespace ppcr_bench {
namespace {

using PclCloud = pcl::PointCloud<pcl::PointXYZ>;

// ICP's relative MSE threshold (see the header comment).
constexpr double kIcpRelativeMse = 1e-5;
// GICP's metre defaults (transformation epsilon, BFGS gradient tolerances), scaled by the radius.
constexpr double kGicpTranslationEpsilon = 5e-4;
constexpr double kGicpGradientTolerance = 1e-2;
// NDT's step thresholds: translation as a fraction of the radius, rotation in radians.
constexpr double kNdtTranslationStep = 1e-3;
constexpr double kNdtRotationStep = 1e-3;

PclCloud::Ptr to_pcl(const ppcr::PointCloud& cloud) {
  PclCloud::Ptr out(new PclCloud);
  out->resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    (*out)[i].x = static_cast<float>(cloud[i].x());
    (*out)[i].y = static_cast<float>(cloud[i].y());
    (*out)[i].z = static_cast<float>(cloud[i].z());
  }
  return out;
}

Eigen::Isometry3d to_isometry(const Eigen::Matrix4f& m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = m.topLeftCorner<3, 3>().cast<double>();
  T.translation() = m.topRightCorner<3, 1>().cast<double>();
  return T;
}

// Exposes the iteration count PCL keeps in the protected Registration::nr_iterations_.
template <typename Registration>
class Counted : public Registration {
 public:
  int iterations() const { return this->nr_iterations_; }
};

MethodResult failed(const std::exception& e) {
  MethodResult out;
  out.ok = false;
  out.message = e.what();
  out.stop_reason = "exception";
  return out;
}

class PclIcp : public Method {
 public:
  explicit PclIcp(const MethodSettings& settings) : settings_(settings) {}
  std::string name() const override { return "pcl-icp"; }

  MethodResult run(const ppcr::PointCloud& source, const ppcr::PointCloud& target) override {
    using Icp = pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>;
    using Criteria = pcl::registration::DefaultConvergenceCriteria<float>;
    try {
      Counted<Icp> icp;
      icp.setInputSource(to_pcl(source));
      icp.setInputTarget(to_pcl(target));
      icp.setMaxCorrespondenceDistance(settings_.max_correspondence);
      icp.setMaximumIterations(settings_.max_iterations);
      icp.setEuclideanFitnessEpsilon(kIcpRelativeMse);
      PclCloud aligned;
      icp.align(aligned);
      MethodResult out;
      out.ok = true;
      out.T_target_source = to_isometry(icp.getFinalTransformation());
      out.iterations = icp.iterations();
      switch (icp.getConvergeCriteria()->getConvergenceState()) {
        case Criteria::CONVERGENCE_CRITERIA_TRANSFORM:
          out.stop_reason = "transform_epsilon";
          out.converged = true;
          break;
        case Criteria::CONVERGENCE_CRITERIA_ABS_MSE:
          out.stop_reason = "abs_mse";
          out.converged = true;
          break;
        case Criteria::CONVERGENCE_CRITERIA_REL_MSE:
          out.stop_reason = "rel_mse";
          out.converged = true;
          break;
        case Criteria::CONVERGENCE_CRITERIA_ITERATIONS:
        case Criteria::CONVERGENCE_CRITERIA_FAILURE_AFTER_MAX_ITERATIONS:
          out.stop_reason = "max_iterations";
          break;
        case Criteria::CONVERGENCE_CRITERIA_NO_CORRESPONDENCES:
          out.stop_reason = "no_correspondences";
          break;
        case Criteria::CONVERGENCE_CRITERIA_NOT_CONVERGED:
          out.stop_reason = "not_converged";
          break;
      }
      return out;
    } catch (const std::exception& e) {
      return failed(e);
    }
  }

 private:
  MethodSettings settings_;
};

class PclGicp : public Method {
 public:
  explicit PclGicp(const MethodSettings& settings) : settings_(settings) {}
  std::string name() const override { return "pcl-gicp"; }

  MethodResult run(const ppcr::PointCloud& source, const ppcr::PointCloud& target) override {
    using Gicp = pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>;
    try {
      Counted<Gicp> gicp;
      gicp.setInputSource(to_pcl(source));
      gicp.setInputTarget(to_pcl(target));
      gicp.setMaxCorrespondenceDistance(settings_.max_correspondence);
      gicp.setMaximumIterations(settings_.max_iterations);
      const double r = settings_.max_correspondence;
      gicp.setTransformationEpsilon(kGicpTranslationEpsilon * r);
      gicp.setTranslationGradientTolerance(kGicpGradientTolerance * r);
      gicp.setRotationGradientTolerance(kGicpGradientTolerance * r * r);
      PclCloud aligned;
      gicp.align(aligned);
      MethodResult out;
      out.ok = true;
      out.T_target_source = to_isometry(gicp.getFinalTransformation());
      out.iterations = gicp.iterations();
      // GICP sets converged_ both on its transform test and on the cap; it leaves it false when
      // the BFGS step threw (too few correspondences, line search failure) or a search failed.
      if (!gicp.hasConverged()) {
        out.stop_reason = "optimizer_failure";
      } else if (out.iterations >= settings_.max_iterations) {
        out.stop_reason = "max_iterations";
      } else {
        out.stop_reason = "transform_epsilon";
        out.converged = true;
      }
      return out;
    } catch (const std::exception& e) {
      return failed(e);
    }
  }

 private:
  MethodSettings settings_;
};

class PclNdt : public Method {
 public:
  explicit PclNdt(const MethodSettings& settings) : settings_(settings) {}
  std::string name() const override { return "pcl-ndt"; }

  MethodResult run(const ppcr::PointCloud& source, const ppcr::PointCloud& target) override {
    using Ndt = pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ>;
    try {
      Ndt ndt;
      // Resolution first: setting it after the target rebuilds the voxel grid.
      ndt.setResolution(static_cast<float>(settings_.ndt_resolution));
      const double step = kNdtTranslationStep * settings_.max_correspondence;
      ndt.setTransformationEpsilon(step * step);
      ndt.setTransformationRotationEpsilon(std::cos(kNdtRotationStep));
      ndt.setMaximumIterations(settings_.max_iterations);
      ndt.setInputTarget(to_pcl(target));
      ndt.setInputSource(to_pcl(source));
      PclCloud aligned;
      ndt.align(aligned);
      MethodResult out;
      out.ok = true;
      out.T_target_source = to_isometry(ndt.getFinalTransformation());
      out.iterations = ndt.getFinalNumIteration();
      // converged_ is set on the step tests, on the cap and on a zero Newton step; it stays
      // false on a NaN step or an empty voxel grid.
      if (!ndt.hasConverged()) {
        out.stop_reason = "failure";
      } else if (out.iterations >= settings_.max_iterations) {
        out.stop_reason = "max_iterations";
      } else {
        out.stop_reason = "transform_epsilon";
        out.converged = true;
      }
      return out;
    } catch (const std::exception& e) {
      return failed(e);
    }
  }

 private:
  MethodSettings settings_;
};

}  // namespace

std::vector<std::string> pcl_methods() { return {"pcl-icp", "pcl-gicp", "pcl-ndt"}; }

std::unique_ptr<Method> make_pcl_method(const std::string& name, const MethodSettings& settings) {
  if (name == "pcl-icp") return std::make_unique<PclIcp>(settings);
  if (name == "pcl-gicp") return std::make_unique<PclGicp>(settings);
  if (name == "pcl-ndt") return std::make_unique<PclNdt>(settings);
  return nullptr;
}

}  // namespace ppcr_bench
