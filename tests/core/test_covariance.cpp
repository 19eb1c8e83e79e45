// Tests of the pose covariance's parts (quality/covariance.hpp): the curvature of the E-step
// objective against central differences of the pass's gradient with the weights refreshed at
// each pose, the cluster sums against a naive per-point reference, thread-count independence,
// and the sandwich on singular and non-finite input.
#include <catch2/catch.hpp>
#include <limits>
#include <vector>

#include "association/association_table.hpp"
#include "association/kdtree.hpp"
#include "core_test_util.hpp"
#include "model/normal_equations.hpp"
#include "ppcr/se3.hpp"
#include "quality/covariance.hpp"

using core_test::Rng;
using ppcr::WeightModel;
using ppcr::detail::CovarianceSums;
using ppcr::detail::Evaluation;
using ppcr::detail::GradientTerms;
using ppcr::detail::Matrix6d;
using ppcr::detail::NormalEquations;
using ppcr::detail::Vector6d;
using ppcr::detail::WeightParams;

namespace {

// Noisy samples of a box's faces (so that the plane model's normals are the faces'), the source
// the same faces sampled again with noise sigma, moved by T^-1, associated at T by the k-d tree.
struct Pair {
  ppcr::PointCloud source, target;
  std::vector<Eigen::Vector3d> target_normals, source_normals;
  ppcr::detail::AssociationTable table;
  Eigen::Isometry3d T;
};

void sample_faces(Rng& rng, std::size_t n, double sigma, ppcr::PointCloud* points,
                  std::vector<Eigen::Vector3d>* normals) {
  for (std::size_t i = 0; i < n; ++i) {
    const int axis = static_cast<int>(i % 3);
    Eigen::Vector3d p(core_test::uniform(rng, -1, 1), core_test::uniform(rng, -1, 1),
                      core_test::uniform(rng, -1, 1));
    p[axis] = (i % 2 == 0 ? 1.0 : -1.0) + core_test::gaussian(rng, sigma);
    points->push_back(p);
    normals->push_back(Eigen::Vector3d::Unit(axis));
  }
}

Pair make_pair(std::uint64_t seed, double sigma) {
  Rng rng(seed);
  Pair pair;
  pair.T = core_test::make_pose(Eigen::Vector3d(0.2, 1.0, -0.3), 0.4, Eigen::Vector3d(0.3, 0, -1));
  sample_faces(rng, 3000, sigma, &pair.target, &pair.target_normals);
  ppcr::PointCloud moved;
  sample_faces(rng, 1500, sigma, &moved, &pair.source_normals);
  const Eigen::Isometry3d T_inverse = pair.T.inverse();
  for (const Eigen::Vector3d& p : moved) pair.source.push_back(T_inverse * p);
  for (Eigen::Vector3d& n : pair.source_normals) n = T_inverse.linear() * n;
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(pair.target).ok());
  pair.table.resize(pair.source.size(), 6);
  ppcr::detail::associate(tree, pair.source, pair.T, 0.15 * 0.15, nullptr, &pair.table);
  return pair;
}

// The plane model of a pair: target normals, and with `pairs` the pair normals too.
struct Plane {
  Plane(const Pair& pair, bool pairs) : source{&pair.source_normals, pair.T.linear()} {
    ppcr::detail::pack_plane_points(pair.target, pair.target_normals, 0.05, nullptr, &points,
                                    &information);
    model.points = &points;
    model.information = &information;
    model.epsilon = 0.05;
    if (pairs) model.pair_source = &source;
  }
  ppcr::detail::PairNormalSource source;
  ppcr::detail::Buffer<ppcr::detail::PlanePoint> points;
  ppcr::detail::Buffer<ppcr::detail::PlaneInformation> information;
  ppcr::detail::PlaneModel model;
};

// One pass at T: H, g and the weights at T.
Evaluation pass(const Pair& pair, const ppcr::detail::PlaneModel* plane, const WeightParams& e_step,
                const Eigen::Isometry3d& T, std::vector<double>* w) {
  NormalEquations equations;
  equations.resize(pair.source.size(), pair.table.k);
  w->assign(pair.source.size() * static_cast<std::size_t>(pair.table.k), 0.0);
  Evaluation out;
  equations.evaluate(pair.source, pair.target, pair.table, e_step, T, nullptr, w->data(), nullptr,
                     nullptr, &out, plane);
  return out;
}

std::vector<WeightParams> weight_models(double sigma) {
  const double inv_scale_sq = 1.0 / (sigma * sigma);
  return {{WeightModel::kStudentT, 1.25, inv_scale_sq},
          {WeightModel::kStudentT, 5.0, inv_scale_sq},
          {WeightModel::kGaussian, 5.0, inv_scale_sq}};
}

double relative(const Matrix6d& a, const Matrix6d& b) { return (a - b).norm() / b.norm(); }

}  // namespace

TEST_CASE("H_GN - curvature / s^2 is the central-difference Hessian of the E-step objective",
          "[covariance]") {
  // The objective's gradient at a pose is the pass's g with the weights of that pose (the EM
  // identity); its derivative is H_true. The Gauss-Newton H_GN ignores how the weights move.
  const double sigma = 0.01;
  const Pair pair = make_pair(11, sigma);
  for (int model = 0; model < 3; ++model) {
    const Plane plane(pair, model == 2);
    const ppcr::detail::PlaneModel* plane_model = model == 0 ? nullptr : &plane.model;
    for (const WeightParams& e_step : weight_models(sigma)) {
      CAPTURE(model, static_cast<int>(e_step.model), e_step.dof);
      std::vector<double> w;
      const Evaluation at_T = pass(pair, plane_model, e_step, pair.T, &w);
      const GradientTerms terms{&pair.source, &pair.table, w.data(), pair.T,
                                &pair.target, plane_model, e_step};
      std::vector<CovarianceSums> clusters;
      const CovarianceSums sums = ppcr::detail::covariance_sums(terms, nullptr, &clusters);
      const Matrix6d H_true = at_T.H - e_step.inv_scale_sq * sums.curvature;
      Matrix6d H_numeric;
      const double h = 1e-6;
      for (int c = 0; c < 6; ++c) {
        Vector6d d = Vector6d::Zero();
        d(c) = h;
        std::vector<double> w_step;
        const Vector6d g_plus =
            pass(pair, plane_model, e_step, ppcr::se3::exp(d) * pair.T, &w_step).g;
        const Vector6d g_minus =
            pass(pair, plane_model, e_step, ppcr::se3::exp(-d) * pair.T, &w_step).g;
        H_numeric.col(c) = (g_plus - g_minus) / (2.0 * h);
      }
      H_numeric = 0.5 * (H_numeric + H_numeric.transpose()).eval();
      // The second-order terms of the error (J's own derivative) are left out of both H: a
      // residual-sized part, about sigma / extent of H.
      CHECK(relative(H_true, H_numeric) < 0.03);
      CHECK(relative(at_T.H, H_numeric) > 0.1);  // the weights' motion matters
    }
  }
}

TEST_CASE(
    "covariance_sums equals a naive per-pair sum over clusters, the same with 1 and 2 threads",
    "[covariance]") {
  const double sigma = 0.01;
  const Pair pair = make_pair(12, sigma);
  const Plane plane(pair, false);
  for (const bool planes : {true, false}) {
    for (const WeightParams& e_step : weight_models(sigma)) {
      CAPTURE(planes, static_cast<int>(e_step.model), e_step.dof);
      const ppcr::detail::PlaneModel* model = planes ? &plane.model : nullptr;
      std::vector<double> w;
      pass(pair, model, e_step, pair.T, &w);
      const GradientTerms terms{&pair.source, &pair.table, w.data(), pair.T,
                                &pair.target, model,       e_step};
      std::vector<CovarianceSums> clusters;
      const CovarianceSums one =
          ppcr::detail::covariance_sums(terms, core_test::parallel(1), &clusters);
      const CovarianceSums two =
          ppcr::detail::covariance_sums(terms, core_test::parallel(2), &clusters);
      CHECK(one.meat == two.meat);
      CHECK(one.curvature == two.curvature);
      // Naive: explicit J and Omega = epsilon I + n n^T per pair.
      const std::size_t k = static_cast<std::size_t>(pair.table.k);
      Matrix6d meat = Matrix6d::Zero(), curvature = Matrix6d::Zero();
      Vector6d G = Vector6d::Zero();
      for (std::size_t j = 0; j < pair.source.size(); ++j) {
        const Eigen::Vector3d p = pair.T * pair.source[j];
        Eigen::Matrix<double, 3, 6> J;
        J << ppcr::se3::skew(p), -Eigen::Matrix3d::Identity();
        Vector6d g = Vector6d::Zero();
        for (std::size_t m = 0; m < pair.table.count[j]; ++m) {
          const std::uint32_t y = pair.table.index[j * k + m];
          const Eigen::Vector3d& n = pair.target_normals[y];
          const Eigen::Matrix3d omega =
              planes ? Eigen::Matrix3d(0.05 * Eigen::Matrix3d::Identity() + n * n.transpose())
                     : Eigen::Matrix3d::Identity();
          const Eigen::Vector3d e = pair.target[y] - p;
          const Vector6d a = J.transpose() * omega * e;
          const double z = e.dot(omega * e) * e_step.inv_scale_sq;
          const double weight = w[j * k + m];
          const double c = e_step.model == WeightModel::kGaussian
                               ? weight
                               : weight * (e_step.dof + 5.0) / (e_step.dof + z);
          g += weight * a;
          curvature += c * a * a.transpose();
        }
        curvature -= g * g.transpose();
        G += g;
        if ((j + 1) % ppcr::detail::kClusterPoints == 0 || j + 1 == pair.source.size()) {
          meat += G * G.transpose();
          G.setZero();
        }
      }
      CHECK(relative(one.meat, meat) < 1e-9);
      CHECK(relative(one.curvature, curvature) < 1e-9);
      CHECK(one.clusters ==
            (pair.source.size() + ppcr::detail::kClusterPoints - 1) / ppcr::detail::kClusterPoints);
    }
  }
}

TEST_CASE("sandwich_covariance: H^-1 M H^-1, finite when H is singular, zero when not finite",
          "[covariance]") {
  Rng rng(3);
  Eigen::Matrix<double, 6, 6> A;
  for (Eigen::Index i = 0; i < A.size(); ++i) A(i) = core_test::uniform(rng, -1.0, 1.0);
  const Matrix6d H = A * A.transpose() + Matrix6d::Identity();
  const Matrix6d M = 0.5 * H;
  const Matrix6d C = ppcr::detail::sandwich_covariance(H, M);
  const Matrix6d expected = ppcr::detail::kCovarianceCalibration * H.inverse() * M * H.inverse();
  CHECK(relative(C, expected) < 1e-10);
  Matrix6d singular = H;
  singular.row(2).setZero();
  singular.col(2).setZero();
  const Matrix6d C_singular = ppcr::detail::sandwich_covariance(singular, M);
  CHECK(C_singular.allFinite());
  Matrix6d not_finite = H;
  not_finite(0, 0) = std::numeric_limits<double>::quiet_NaN();
  CHECK(ppcr::detail::sandwich_covariance(not_finite, M).isZero(0.0));
  CHECK(ppcr::detail::sandwich_covariance(Matrix6d::Zero(), M).isZero(0.0));
}
