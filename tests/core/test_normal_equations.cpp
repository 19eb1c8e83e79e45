// Tests of detail::NormalEquations::evaluate against a naive per-pair reference (explicit 3x6
// Jacobians, sum of w J^T J over every pair), against Jacobians and gradients obtained by central
// differences of the error through ppcr::se3::exp (so the analytic form is not trusted), and for
// independence of the thread count.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <utility>
#include <vector>

#include "association/association_table.hpp"
#include "association/kdtree.hpp"
#include "common/parallel.hpp"
#include "core_test_util.hpp"
#include "model/e_step.hpp"
#include "model/four_lanes.hpp"
#include "model/four_points.hpp"
#include "model/normal_equations.hpp"
#include "pair_normal_reference.hpp"
#include "ppcr/se3.hpp"

using core_test::Rng;
using ppcr::PointCloud;
using ppcr::detail::AssociationTable;
using ppcr::detail::Evaluation;
using ppcr::detail::Matrix6d;
using ppcr::detail::NormalEquations;
using ppcr::detail::Vector6d;
using ppcr::detail::WeightParams;
using Jacobian = Eigen::Matrix<double, 3, 6>;

namespace {

struct Problem {
  PointCloud source, target;
  AssociationTable assoc;
  Eigen::Isometry3d T;
};

// A source near the target under T (noisy), associated by the real k-d tree at T.
Problem make_problem(std::uint64_t seed, std::size_t n, int k, double radius) {
  Rng rng(seed);
  Problem pb;
  pb.target = core_test::uniform_cloud(rng, n, -1.0, 1.0);
  pb.T = core_test::make_pose(Eigen::Vector3d(0.3, 1.0, -0.2), core_test::deg2rad(25.0),
                              Eigen::Vector3d(0.4, -0.3, 0.2));
  const Eigen::Isometry3d T_inv = pb.T.inverse();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d noisy = pb.target[i] + Eigen::Vector3d(core_test::gaussian(rng, 0.02),
                                                                 core_test::gaussian(rng, 0.02),
                                                                 core_test::gaussian(rng, 0.02));
    pb.source.push_back(T_inv * noisy);
  }
  // Some source points far from everything: no association.
  for (std::size_t i = 0; i < n / 20; ++i) pb.source[i * 20] = T_inv * Eigen::Vector3d(5, 5, 5);
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(pb.target).ok());
  pb.assoc.resize(pb.source.size(), k);
  ppcr::detail::associate(tree, pb.source, pb.T, radius * radius, nullptr, &pb.assoc);
  return pb;
}

// J of e = y - p at delta = 0, written out: [ [p]_x | -I ].
Jacobian analytic_jacobian(const Eigen::Vector3d& p) {
  Jacobian J;
  J << 0.0, -p.z(), p.y(), -1, 0, 0,  //
      p.z(), 0.0, -p.x(), 0, -1, 0,   //
      -p.y(), p.x(), 0.0, 0, 0, -1;
  return J;
}

// J of e(delta) = y - exp(delta) T x at delta = 0 by central differences (y drops out).
Jacobian numeric_jacobian(const Eigen::Isometry3d& T, const Eigen::Vector3d& x) {
  const double h = 1e-6;
  Jacobian J;
  for (int c = 0; c < 6; ++c) {
    Vector6d d = Vector6d::Zero();
    d(c) = h;
    J.col(c) = -((ppcr::se3::exp(d) * T) * x - (ppcr::se3::exp(-d) * T) * x) / (2.0 * h);
  }
  return J;
}

struct Reference {
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  double cost = 0.0, cost_prev = 0.0, weight_sum = 0.0;
  std::vector<double> w, r_sq;
};

// The naive reference: one 3x6 Jacobian and one 6x6 outer product per PAIR.
Reference naive(const Problem& pb, const WeightParams& wp, const Eigen::Isometry3d& T,
                const double* w_prev, bool numeric_J) {
  const std::size_t k = static_cast<std::size_t>(pb.assoc.k);
  Reference ref;
  ref.w.assign(pb.source.size() * k, 0.0);
  ref.r_sq.assign(pb.source.size() * k, 0.0);
  for (std::size_t j = 0; j < pb.source.size(); ++j) {
    const std::size_t count = pb.assoc.count[j];
    if (count == 0) continue;
    const Eigen::Vector3d p = T * pb.source[j];
    for (std::size_t m = 0; m < count; ++m) {
      ref.r_sq[j * k + m] = (pb.target[pb.assoc.index[j * k + m]] - p).squaredNorm();
    }
    ppcr::compute_weights(wp.model, wp.dof, wp.inv_scale_sq, &ref.r_sq[j * k], count,
                          &ref.w[j * k]);
    const Jacobian J = numeric_J ? numeric_jacobian(T, pb.source[j]) : analytic_jacobian(p);
    for (std::size_t m = 0; m < count; ++m) {
      const double w = ref.w[j * k + m];
      const Eigen::Vector3d e = pb.target[pb.assoc.index[j * k + m]] - p;
      ref.H += w * J.transpose() * J;
      ref.g += w * J.transpose() * e;
      ref.cost += 0.5 * w * e.squaredNorm();
      ref.weight_sum += w;
      if (w_prev != nullptr) ref.cost_prev += 0.5 * w_prev[j * k + m] * e.squaredNorm();
    }
  }
  return ref;
}

// Omega of a target point (ppcr/options.hpp, ErrorModel): epsilon I + n n^T with a normal, I
// without.
Eigen::Matrix3d omega(const Eigen::Vector3d& n, double epsilon) {
  if (n.squaredNorm() == 0.0) return Eigen::Matrix3d::Identity();
  return epsilon * Eigen::Matrix3d::Identity() + n * n.transpose();
}

// The naive plane-model reference: r = e^T Omega e, one 6x6 term w J^T Omega J per PAIR. With
// pair_normals, slot j*k+m uses its own normal instead of its target point's.
Reference naive_plane(const Problem& pb, const WeightParams& wp, const Eigen::Isometry3d& T,
                      const double* w_prev, const std::vector<Eigen::Vector3d>& normals,
                      double epsilon, const std::vector<Eigen::Vector3d>* pair_normals = nullptr) {
  const std::size_t k = static_cast<std::size_t>(pb.assoc.k);
  Reference ref;
  ref.w.assign(pb.source.size() * k, 0.0);
  ref.r_sq.assign(pb.source.size() * k, 0.0);
  for (std::size_t j = 0; j < pb.source.size(); ++j) {
    const std::size_t count = pb.assoc.count[j];
    if (count == 0) continue;
    const Eigen::Vector3d p = T * pb.source[j];
    for (std::size_t m = 0; m < count; ++m) {
      const std::uint32_t y = pb.assoc.index[j * k + m];
      const Eigen::Vector3d e = pb.target[y] - p;
      const Eigen::Vector3d& n = pair_normals ? (*pair_normals)[j * k + m] : normals[y];
      ref.r_sq[j * k + m] = e.dot(omega(n, epsilon) * e);
    }
    ppcr::compute_weights(wp.model, wp.dof, wp.inv_scale_sq, &ref.r_sq[j * k], count,
                          &ref.w[j * k]);
    const Jacobian J = analytic_jacobian(p);
    for (std::size_t m = 0; m < count; ++m) {
      const std::uint32_t y = pb.assoc.index[j * k + m];
      const double w = ref.w[j * k + m];
      const Eigen::Vector3d e = pb.target[y] - p;
      const Eigen::Matrix3d O =
          omega(pair_normals ? (*pair_normals)[j * k + m] : normals[y], epsilon);
      ref.H += w * J.transpose() * O * J;
      ref.g += w * J.transpose() * O * e;
      ref.cost += 0.5 * w * ref.r_sq[j * k + m];
      ref.weight_sum += w;
      if (w_prev != nullptr) ref.cost_prev += 0.5 * w_prev[j * k + m] * ref.r_sq[j * k + m];
    }
  }
  return ref;
}

// Unit normals for most target points, none (zero) for every fifth.
std::vector<Eigen::Vector3d> random_normals(std::size_t n, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Eigen::Vector3d> normals(n);
  for (std::size_t i = 0; i < n; ++i) {
    normals[i] = i % 5 == 0 ? Eigen::Vector3d::Zero() : core_test::random_unit_vector(rng);
  }
  return normals;
}

// The rotation at which a test's pair normals are frozen (PairNormalSource).
Eigen::Matrix3d pair_rotation() {
  return core_test::make_pose(Eigen::Vector3d(0.3, -1.0, 0.4), 0.9, Eigen::Vector3d::Zero())
      .linear();
}

// The plane model over pb's target with the given normals (kept: the references read them), or
// with random_normals(seed). Not copyable: the model points at the packed points.
struct PackedPlane {
  PackedPlane(const Problem& pb, std::vector<Eigen::Vector3d> target_normals, double epsilon)
      : normals(std::move(target_normals)) {
    ppcr::detail::pack_plane_points(pb.target, normals, epsilon, nullptr, &points, &information);
    model.points = &points;
    model.information = &information;
    model.epsilon = epsilon;
  }
  PackedPlane(const Problem& pb, std::uint64_t normals_seed, double epsilon)
      : PackedPlane(pb, random_normals(pb.target.size(), normals_seed), epsilon) {}
  PackedPlane(const PackedPlane&) = delete;
  PackedPlane& operator=(const PackedPlane&) = delete;
  std::vector<Eigen::Vector3d> normals;
  ppcr::detail::Buffer<ppcr::detail::PlanePoint> points;
  ppcr::detail::Buffer<ppcr::detail::PlaneInformation> information;
  ppcr::detail::PlaneModel model;
};

// A problem's three models of the pass (point, plane, plane with pair normals: the point model
// is null) and random previous weights, for the tests that compare passes under every model:
// target normals from `seed`, source normals from seed + 1, weights from seed + 2.
struct EveryModel {
  EveryModel(const Problem& pb, std::uint64_t seed)
      : packed(pb, seed, 0.05),
        packed_pairs(pb, seed, 0.05),
        source_normals(random_normals(pb.source.size(), seed + 1)),
        pair_source{&source_normals, pair_rotation()} {
    packed_pairs.model.pair_source = &pair_source;
    Rng rng(seed + 2);
    w_prev.resize(pb.source.size() * static_cast<std::size_t>(pb.assoc.k));
    for (double& w : w_prev) w = core_test::uniform(rng, 0.0, 1.0);
  }
  std::vector<const ppcr::detail::PlaneModel*> models() const {
    return {nullptr, &packed.model, &packed_pairs.model};
  }
  PackedPlane packed, packed_pairs;
  std::vector<Eigen::Vector3d> source_normals;
  ppcr::detail::PairNormalSource pair_source;
  std::vector<double> w_prev;
};

struct Output {
  Evaluation eval;
  std::vector<double> w, r_sq;
};

// with_r_sq = false: no squared-error array (as the LM solver calls it); out.r_sq stays empty.
Output run(const Problem& pb, const WeightParams& wp, const Eigen::Isometry3d& T,
           const double* w_prev, int threads, const ppcr::detail::PlaneModel* plane = nullptr,
           bool with_r_sq = true) {
  NormalEquations ne;
  ne.resize(pb.source.size(), pb.assoc.k);
  Output out;
  const std::size_t slots = pb.source.size() * static_cast<std::size_t>(pb.assoc.k);
  out.w.assign(slots, 0.0);
  if (with_r_sq) out.r_sq.assign(slots, 0.0);
  ne.evaluate(pb.source, pb.target, pb.assoc, wp, T, w_prev, out.w.data(),
              with_r_sq ? out.r_sq.data() : nullptr, core_test::parallel(threads), &out.eval,
              plane);
  return out;
}

// Central differences (step h on each twist coordinate) of cost(delta) at delta = 0.
template <class Cost>
Vector6d central_gradient(const Cost& cost, double h = 1e-6) {
  Vector6d g;
  for (int c = 0; c < 6; ++c) {
    Vector6d d = Vector6d::Zero();
    d(c) = h;
    g(c) = (cost(d) - cost(-d)) / (2.0 * h);
  }
  return g;
}

double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

std::vector<WeightParams> weight_params() {
  std::vector<WeightParams> out(4);
  out[0] = {ppcr::WeightModel::kStudentT, 5.0, 1.0};
  out[1] = {ppcr::WeightModel::kStudentT, 3.0, 1.0 / (0.05 * 0.05)};
  out[2] = {ppcr::WeightModel::kGaussian, 5.0, 1.0};
  out[3] = {ppcr::WeightModel::kGaussian, 5.0, 1.0 / (0.08 * 0.08)};
  return out;
}

}  // namespace

TEST_CASE("evaluate equals the naive per-pair sums (explicit Jacobians)", "[normal_equations]") {
  const Problem pb = make_problem(51, 700, 8, 0.15);
  REQUIRE(pb.assoc.pairs > 1000u);
  REQUIRE(pb.assoc.matched < pb.source.size());  // some points without neighbours
  for (const WeightParams& wp : weight_params()) {
    // At the association pose and at a pose moved away from it.
    for (const Eigen::Isometry3d& T :
         {pb.T, core_test::make_pose(Eigen::Vector3d(1, 0, 0), 0.03, Eigen::Vector3d(0.01, 0, 0)) *
                    pb.T}) {
      const Reference ref = naive(pb, wp, T, nullptr, false);
      const Output out = run(pb, wp, T, nullptr, 1);
      INFO("model " << static_cast<int>(wp.model) << " inv_s2 " << wp.inv_scale_sq);
      CHECK(rel_diff(out.eval.H, ref.H) < 1e-12);
      CHECK(rel_diff(out.eval.g, ref.g) < 1e-11);
      CHECK(std::abs(out.eval.cost - ref.cost) < 1e-12 * ref.cost);
      CHECK(std::abs(out.eval.weight_sum - ref.weight_sum) < 1e-12 * ref.weight_sum);
      CHECK(out.eval.cost_prev_weights == 0.0);
      const std::size_t k = static_cast<std::size_t>(pb.assoc.k);
      double max_w = 0.0, max_r = 0.0;
      for (std::size_t j = 0; j < pb.source.size(); ++j) {
        for (std::size_t m = 0; m < pb.assoc.count[j]; ++m) {
          max_w = std::max(max_w, std::abs(out.w[j * k + m] - ref.w[j * k + m]) /
                                      std::max(ref.w[j * k + m], 1e-300));
          max_r = std::max(max_r, std::abs(out.r_sq[j * k + m] - ref.r_sq[j * k + m]) /
                                      std::max(ref.r_sq[j * k + m], 1e-300));
        }
      }
      CHECK(max_w < 1e-9);
      CHECK(max_r < 1e-9);
    }
  }
}

TEST_CASE("the analytic Jacobian equals central differences of the error", "[normal_equations]") {
  Rng rng(52);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Isometry3d T = core_test::make_pose(
        core_test::random_unit_vector(rng), core_test::uniform(rng, 0.0, 3.0),
        core_test::uniform(rng, 0.0, 3.0) * core_test::random_unit_vector(rng));
    const Eigen::Vector3d x =
        core_test::uniform(rng, 0.0, 3.0) * core_test::random_unit_vector(rng);
    const Jacobian Jn = numeric_jacobian(T, x);
    const Jacobian Ja = analytic_jacobian(T * x);
    CHECK((Jn - Ja).cwiseAbs().maxCoeff() < 1e-8 * (1.0 + (T * x).norm()));
  }
}

TEST_CASE("evaluate equals per-pair sums built from NUMERIC Jacobians", "[normal_equations]") {
  // Independent of the analytic form of J: J by central differences through se3::exp.
  const Problem pb = make_problem(53, 400, 6, 0.15);
  for (const WeightParams& wp : weight_params()) {
    const Reference ref = naive(pb, wp, pb.T, nullptr, true);
    const Output out = run(pb, wp, pb.T, nullptr, 1);
    CHECK(rel_diff(out.eval.H, ref.H) < 1e-7);
    CHECK(rel_diff(out.eval.g, ref.g) < 1e-7);
  }
}

TEST_CASE("g is the central-difference gradient of the cost under fixed weights",
          "[normal_equations]") {
  const Problem pb = make_problem(54, 500, 6, 0.15);
  for (const WeightParams& wp : weight_params()) {
    const Output at = run(pb, wp, pb.T, nullptr, 1);
    const std::vector<double>& w_fixed = at.w;
    // cost(delta) = 1/2 sum w_fixed |y - exp(delta) T x|^2, through the cost_prev_weights path.
    auto cost = [&](const Vector6d& d) {
      return run(pb, wp, ppcr::se3::exp(d) * pb.T, w_fixed.data(), 1).eval.cost_prev_weights;
    };
    // At delta = 0 the fixed weights ARE the weights of the pose: both costs agree.
    CHECK(std::abs(cost(Vector6d::Zero()) - at.eval.cost) <= 1e-14 * at.eval.cost);
    const Vector6d g_num = central_gradient(cost);
    INFO("analytic " << at.eval.g.transpose() << "\nnumeric  " << g_num.transpose());
    CHECK(rel_diff(at.eval.g, g_num) < 1e-6);
  }
}

TEST_CASE("H is the Hessian of the fixed-weight cost when the residuals vanish",
          "[normal_equations]") {
  // k = 1 exact correspondences: the Gauss-Newton matrix is then the exact Hessian, which second
  // differences of the fixed-weight cost give independently.
  Rng rng(55);
  Problem pb;
  pb.source = core_test::uniform_cloud(rng, 300, -1.0, 1.0);
  pb.T = core_test::make_pose(Eigen::Vector3d(1, 2, 3), 0.4, Eigen::Vector3d(0.3, 0.2, 0.1));
  pb.target = core_test::transformed(pb.source, pb.T);
  pb.assoc.resize(pb.source.size(), 1);
  for (std::size_t j = 0; j < pb.source.size(); ++j) {
    pb.assoc.index[j] = static_cast<std::uint32_t>(j);
    pb.assoc.count[j] = 1;
  }
  pb.assoc.pairs = pb.assoc.matched = pb.source.size();
  const WeightParams wp{ppcr::WeightModel::kStudentT, 5.0, 1.0};
  const Output at = run(pb, wp, pb.T, nullptr, 1);
  CHECK(at.eval.cost < 1e-25);
  auto cost = [&](const Vector6d& d) {
    return run(pb, wp, ppcr::se3::exp(d) * pb.T, at.w.data(), 1).eval.cost_prev_weights;
  };
  const double h = 1e-4;
  Matrix6d H_num;
  for (int a = 0; a < 6; ++a) {
    for (int b = 0; b < 6; ++b) {
      Vector6d da = Vector6d::Zero(), db = Vector6d::Zero();
      da(a) = h;
      db(b) = h;
      H_num(a, b) =
          (cost(da + db) - cost(da - db) - cost(-da + db) + cost(-da - db)) / (4.0 * h * h);
    }
  }
  INFO("H\n" << at.eval.H << "\nnumeric\n" << H_num);
  CHECK(rel_diff(at.eval.H, H_num) < 1e-5);
}

TEST_CASE("cost_prev_weights is the cost at the pose under the given weights",
          "[normal_equations]") {
  const Problem pb = make_problem(56, 600, 5, 0.2);
  Rng rng(57);
  std::vector<double> w_prev(pb.source.size() * 5);
  for (double& w : w_prev) w = core_test::uniform(rng, 0.0, 2.0);
  for (const WeightParams& wp : weight_params()) {
    const Eigen::Isometry3d T =
        core_test::make_pose(Eigen::Vector3d(0, 1, 0), 0.05, Eigen::Vector3d(0, 0, 0.02)) * pb.T;
    const Reference ref = naive(pb, wp, T, w_prev.data(), false);
    const Output out = run(pb, wp, T, w_prev.data(), 1);
    CHECK(std::abs(out.eval.cost_prev_weights - ref.cost_prev) < 1e-12 * ref.cost_prev);
    // The new weights and everything under them are unaffected by w_prev.
    const Output plain = run(pb, wp, T, nullptr, 1);
    CHECK(out.eval.H == plain.eval.H);
    CHECK(out.eval.g == plain.eval.g);
    CHECK(out.eval.cost == plain.eval.cost);
  }
}

TEST_CASE("points without neighbours contribute nothing, no pairs gives zeros",
          "[normal_equations]") {
  Rng rng(58);
  Problem pb;
  pb.source = core_test::uniform_cloud(rng, 100, -1.0, 1.0);
  pb.target = core_test::uniform_cloud(rng, 100, -1.0, 1.0);
  pb.T = Eigen::Isometry3d::Identity();
  pb.assoc.resize(pb.source.size(), 3);  // all counts zero
  const WeightParams wp;
  const Output out = run(pb, wp, pb.T, nullptr, 2);
  CHECK(out.eval.H == Matrix6d::Zero());
  CHECK(out.eval.g == Vector6d::Zero());
  CHECK(out.eval.cost == 0.0);
  CHECK(out.eval.weight_sum == 0.0);
  // Hand-made table: only point 7 has neighbours; equals the naive sum of that point alone.
  pb.assoc.count[7] = 2;
  pb.assoc.index[21] = 3;
  pb.assoc.index[22] = 50;
  pb.assoc.pairs = 2;
  pb.assoc.matched = 1;
  const Reference ref = naive(pb, wp, pb.T, nullptr, false);
  const Output one = run(pb, wp, pb.T, nullptr, 1);
  CHECK(rel_diff(one.eval.H, ref.H) < 1e-14);
  CHECK(rel_diff(one.eval.g, ref.g) < 1e-14);
}

TEST_CASE("rows left out (AssociationTable::left_out) are as rows without pairs, weights 0",
          "[normal_equations]") {
  // Every third matched row left out, as the associator leaves out rows beyond the target's
  // boundary: the sums equal, to the bit, those of the same table with those rows emptied; the
  // rows' weights are 0; normal_information skips them too. Every model, both thread counts.
  const int k = 6;
  const Problem pb = make_problem(91, 3000, k, 0.08);
  Problem emptied = pb;
  Problem left = pb;
  left.assoc.left_out.assign(pb.source.size(), 0);  // sized by whoever leaves rows out
  std::size_t out = 0;
  for (std::size_t j = 0; j < pb.source.size(); ++j) {
    const bool leave = pb.assoc.count[j] > 0 && j % 3 == 0;
    left.assoc.left_out[j] = leave;
    if (leave) emptied.assoc.count[j] = 0;
    out += leave;
  }
  REQUIRE(out > 500);
  left.assoc.any_left_out = true;
  left.assoc.recount();
  emptied.assoc.recount();
  CHECK(left.assoc.pairs == emptied.assoc.pairs);
  CHECK(left.assoc.matched == emptied.assoc.matched);
  CHECK(left.assoc.matched + out == pb.assoc.matched);
  const EveryModel every(pb, 92);
  const std::vector<double>& w_prev = every.w_prev;
  const WeightParams wp;
  for (const ppcr::detail::PlaneModel* model : every.models()) {
    for (int threads : {1, 2}) {
      INFO("plane " << (model != nullptr) << " pair normals "
                    << (model != nullptr && model->pair_source != nullptr) << " threads "
                    << threads);
      const Output a = run(left, wp, pb.T, w_prev.data(), threads, model);
      const Output b = run(emptied, wp, pb.T, w_prev.data(), threads, model);
      CHECK(a.eval.H == b.eval.H);
      CHECK(a.eval.g == b.eval.g);
      CHECK(a.eval.cost == b.eval.cost);
      CHECK(a.eval.cost_prev_weights == b.eval.cost_prev_weights);
      CHECK(a.eval.weight_sum == b.eval.weight_sum);
      std::size_t nonzero = 0;
      for (std::size_t j = 0; j < pb.source.size(); ++j) {
        for (std::size_t m = 0; m < pb.assoc.count[j]; ++m) {
          if (left.assoc.left_out[j]) nonzero += a.w[j * k + m] != 0.0;
        }
      }
      CHECK(nonzero == 0);
      if (model != nullptr) {
        std::vector<Matrix6d> blocks;
        const ppcr::detail::Buffer<ppcr::detail::PlanePoint>& points = every.packed.points;
        CHECK(NormalEquations::normal_information(pb.source, left.assoc, pb.T, a.w.data(), points,
                                                  core_test::parallel(threads), &blocks) ==
              NormalEquations::normal_information(pb.source, emptied.assoc, pb.T, b.w.data(),
                                                  points, core_test::parallel(threads), &blocks));
      }
    }
  }
}

TEST_CASE("evaluate is bit-identical with 1 and 2 threads (~10k points, blocks of 256)",
          "[normal_equations]") {
  const Problem pb = make_problem(59, 10000, 10, 0.08);
  REQUIRE(pb.source.size() > 20 * NormalEquations::kBlockSize);
  Rng rng(60);
  std::vector<double> w_prev(pb.source.size() * 10);
  for (double& w : w_prev) w = core_test::uniform(rng, 0.0, 1.0);
  for (const WeightParams& wp : weight_params()) {
    const Output one = run(pb, wp, pb.T, w_prev.data(), 1);
    const Output two = run(pb, wp, pb.T, w_prev.data(), 2);
    CHECK(one.eval.H == two.eval.H);
    CHECK(one.eval.g == two.eval.g);
    CHECK(one.eval.cost == two.eval.cost);
    CHECK(one.eval.cost_prev_weights == two.eval.cost_prev_weights);
    CHECK(one.eval.weight_sum == two.eval.weight_sum);
    CHECK(one.w == two.w);
    CHECK(one.r_sq == two.r_sq);
  }
}

TEST_CASE("evaluate without the r_sq array gives the same weights and sums, both models",
          "[normal_equations]") {
  const Problem pb = make_problem(67, 3000, 10, 0.08);
  PackedPlane packed(pb, 68, 0.05);
  ppcr::detail::PlaneModel& plane = packed.model;
  Rng rng(69);
  std::vector<double> w_prev(pb.source.size() * 10);
  for (double& w : w_prev) w = core_test::uniform(rng, 0.0, 1.0);
  for (const ppcr::detail::PlaneModel* model :
       {static_cast<ppcr::detail::PlaneModel*>(nullptr), &plane}) {
    for (const WeightParams& wp : weight_params()) {
      for (int threads : {1, 2}) {
        const Output with = run(pb, wp, pb.T, w_prev.data(), threads, model);
        const Output without = run(pb, wp, pb.T, w_prev.data(), threads, model, false);
        INFO("plane " << (model != nullptr) << " threads " << threads);
        CHECK(without.eval.H == with.eval.H);
        CHECK(without.eval.g == with.eval.g);
        CHECK(without.eval.cost == with.eval.cost);
        CHECK(without.eval.cost_prev_weights == with.eval.cost_prev_weights);
        CHECK(without.eval.weight_sum == with.eval.weight_sum);
        CHECK(without.w == with.w);
        CHECK(without.r_sq.empty());
      }
    }
  }
}

TEST_CASE("evaluate in place (w_prev = w_new) equals separate arrays, every model and kernel",
          "[normal_equations]") {
  // The LM solver refreshes one weight array in place: every point's previous weights must be
  // read before its new ones are written. Point model, plane model, plane model with pair
  // normals; Student-t with e = 4 (dof 5), 3 (dof 3) and 2.65 (dof 2.3: std::pow), Gaussian; and
  // a pose 10 away at inv_scale_sq = 1e308, where every z_k overflows (the overflow kernels:
  // r >= 0.05 x 9.9^2 even along a plane).
  const int k = 10;
  const Problem pb = make_problem(75, 3000, k, 0.08);
  const EveryModel every(pb, 76);
  const std::vector<double>& w_prev = every.w_prev;
  std::vector<WeightParams> params = weight_params();
  params.push_back({ppcr::WeightModel::kStudentT, 2.3, 1.0 / (0.05 * 0.05)});
  params.push_back({ppcr::WeightModel::kStudentT, 5.0, 1e308});
  params.push_back({ppcr::WeightModel::kGaussian, 5.0, 1e308});
  Eigen::Isometry3d T_far = pb.T;
  T_far.pretranslate(Eigen::Vector3d(10.0, 0.0, 0.0));
  for (const ppcr::detail::PlaneModel* model : every.models()) {
    for (const WeightParams& wp : params) {
      const Eigen::Isometry3d& T = wp.inv_scale_sq > 1e300 ? T_far : pb.T;
      for (int threads : {1, 2}) {
        const Output separate = run(pb, wp, T, w_prev.data(), threads, model, false);
        NormalEquations ne;
        ne.resize(pb.source.size(), pb.assoc.k);
        std::vector<double> w = w_prev;
        Evaluation in_place;
        ne.evaluate(pb.source, pb.target, pb.assoc, wp, T, w.data(), w.data(), nullptr,
                    core_test::parallel(threads), &in_place, model);
        INFO("plane " << (model != nullptr) << " pair normals "
                      << (model != nullptr && model->pair_source != nullptr) << " dof " << wp.dof
                      << " inv_scale_sq " << wp.inv_scale_sq << " threads " << threads);
        CHECK(in_place.cost_prev_weights == separate.eval.cost_prev_weights);
        CHECK(in_place.cost == separate.eval.cost);
        CHECK(in_place.weight_sum == separate.eval.weight_sum);
        CHECK(in_place.H == separate.eval.H);
        CHECK(in_place.g == separate.eval.g);
        // Slots the pass writes (m < count) hold the new weights; the others keep w_prev.
        std::size_t differ = 0, kept = 0, unwritten = 0;
        for (std::size_t j = 0; j < pb.source.size(); ++j) {
          for (std::size_t m = 0; m < static_cast<std::size_t>(k); ++m) {
            const std::size_t slot = j * k + m;
            if (m < pb.assoc.count[j]) {
              differ += w[slot] != separate.w[slot];
            } else {
              ++unwritten;
              kept += w[slot] == w_prev[slot];
            }
          }
        }
        CHECK(differ == 0);
        CHECK(kept == unwritten);
        CHECK(unwritten > 0);
        // The previous weights mattered: the cost under them differs from the cost under the new.
        CHECK(separate.eval.cost_prev_weights != separate.eval.cost);
        // Student-t's overflow kernel gives every weight 0 (c = 0); the ordinary one would not.
        if (wp.inv_scale_sq > 1e300 && wp.model == ppcr::WeightModel::kStudentT) {
          CHECK(separate.eval.weight_sum == 0.0);
        }
      }
    }
  }
}

// ------------------------------------------------------------------------------ plane model

TEST_CASE("plane model: evaluate equals the naive per-pair sums with Omega", "[normal_equations]") {
  const Problem pb = make_problem(61, 600, 6, 0.15);
  Rng rng(63);
  std::vector<double> w_prev(pb.source.size() * 6);
  for (double& w : w_prev) w = core_test::uniform(rng, 0.0, 2.0);
  for (double epsilon : {0.05, 0.3, 1.0}) {
    PackedPlane packed(pb, 62, epsilon);
    ppcr::detail::PlaneModel& plane = packed.model;
    for (const WeightParams& wp : weight_params()) {
      const Eigen::Isometry3d T =
          core_test::make_pose(Eigen::Vector3d(1, 0, 1), 0.02, Eigen::Vector3d(0, 0.01, 0)) * pb.T;
      const Reference ref = naive_plane(pb, wp, T, w_prev.data(), packed.normals, epsilon);
      const Output out = run(pb, wp, T, w_prev.data(), 1, &plane);
      INFO("epsilon " << epsilon << " model " << static_cast<int>(wp.model) << " inv_s2 "
                      << wp.inv_scale_sq);
      CHECK(rel_diff(out.eval.H, ref.H) < 1e-12);
      CHECK(rel_diff(out.eval.g, ref.g) < 1e-11);
      CHECK(std::abs(out.eval.cost - ref.cost) < 1e-12 * ref.cost);
      CHECK(std::abs(out.eval.cost_prev_weights - ref.cost_prev) < 1e-12 * ref.cost_prev);
      CHECK(std::abs(out.eval.weight_sum - ref.weight_sum) < 1e-12 * ref.weight_sum);
      double max_r = 0.0;
      for (std::size_t i = 0; i < ref.r_sq.size(); ++i) {
        if (ref.r_sq[i] == 0.0) continue;  // unused slot
        max_r = std::max(max_r, std::abs(out.r_sq[i] - ref.r_sq[i]) / ref.r_sq[i]);
      }
      CHECK(max_r < 1e-9);
      // Two threads: bit-identical.
      const Output two = run(pb, wp, T, w_prev.data(), 2, &plane);
      CHECK(two.eval.H == out.eval.H);
      CHECK(two.eval.g == out.eval.g);
      CHECK(two.eval.cost == out.eval.cost);
    }
  }
}

TEST_CASE("plane model: g is the central-difference gradient of the fixed-weight cost",
          "[normal_equations]") {
  const Problem pb = make_problem(64, 500, 6, 0.15);
  PackedPlane packed(pb, 65, 0.05);
  ppcr::detail::PlaneModel& plane = packed.model;
  for (const WeightParams& wp : weight_params()) {
    const Output at = run(pb, wp, pb.T, nullptr, 1, &plane);
    auto cost = [&](const Vector6d& d) {
      return run(pb, wp, ppcr::se3::exp(d) * pb.T, at.w.data(), 1, &plane).eval.cost_prev_weights;
    };
    CHECK(std::abs(cost(Vector6d::Zero()) - at.eval.cost) <= 1e-14 * at.eval.cost);
    const Vector6d g_num = central_gradient(cost);
    INFO("analytic " << at.eval.g.transpose() << "\nnumeric  " << g_num.transpose());
    CHECK(rel_diff(at.eval.g, g_num) < 1e-6);
  }
}

TEST_CASE("plane model: H is the Hessian of the fixed-weight cost at zero residuals",
          "[normal_equations]") {
  Rng rng(66);
  Problem pb;
  pb.source = core_test::uniform_cloud(rng, 300, -1.0, 1.0);
  pb.T = core_test::make_pose(Eigen::Vector3d(1, 2, 3), 0.4, Eigen::Vector3d(0.3, 0.2, 0.1));
  pb.target = core_test::transformed(pb.source, pb.T);
  pb.assoc.resize(pb.source.size(), 1);
  for (std::size_t j = 0; j < pb.source.size(); ++j) {
    pb.assoc.index[j] = static_cast<std::uint32_t>(j);
    pb.assoc.count[j] = 1;
  }
  pb.assoc.pairs = pb.assoc.matched = pb.source.size();
  PackedPlane packed(pb, 67, 0.05);
  ppcr::detail::PlaneModel& plane = packed.model;
  const WeightParams wp{ppcr::WeightModel::kStudentT, 5.0, 1.0};
  const Output at = run(pb, wp, pb.T, nullptr, 1, &plane);
  auto cost = [&](const Vector6d& d) {
    return run(pb, wp, ppcr::se3::exp(d) * pb.T, at.w.data(), 1, &plane).eval.cost_prev_weights;
  };
  const double h = 1e-4;
  Matrix6d H_num;
  for (int a = 0; a < 6; ++a) {
    for (int b = 0; b < 6; ++b) {
      Vector6d da = Vector6d::Zero(), db = Vector6d::Zero();
      da(a) = h;
      db(b) = h;
      H_num(a, b) =
          (cost(da + db) - cost(da - db) - cost(-da + db) + cost(-da - db)) / (4.0 * h * h);
    }
  }
  INFO("H\n" << at.eval.H << "\nnumeric\n" << H_num);
  CHECK(rel_diff(at.eval.H, H_num) < 1e-5);
}

TEST_CASE("plane model with pair normals: naive sums with Omega_kj, central-difference gradient",
          "[normal_equations]") {
  const Problem pb = make_problem(71, 600, 6, 0.15);
  // A source normal for every source point (every fifth zero), rotated by R: the pair normals,
  // formed in the pass, must replace the target points' normals everywhere.
  const std::vector<Eigen::Vector3d> source_normals = random_normals(pb.source.size(), 73);
  const ppcr::detail::PairNormalSource pair_source{&source_normals, pair_rotation()};
  Rng rng(74);
  std::vector<double> w_prev(pb.source.size() * 6);
  for (double& w : w_prev) w = core_test::uniform(rng, 0.0, 2.0);
  PackedPlane packed(pb, 72, 0.05);
  ppcr::detail::PlaneModel& plane = packed.model;
  plane.pair_source = &pair_source;
  const std::vector<Eigen::Vector3d> pair = core_test::reference_pair_normals(
      pb.assoc, packed.normals, source_normals, pair_source.R_target_source);
  for (const WeightParams& wp : weight_params()) {
    const Eigen::Isometry3d T =
        core_test::make_pose(Eigen::Vector3d(0, 1, 1), 0.03, Eigen::Vector3d(0.01, 0, 0)) * pb.T;
    const Reference ref = naive_plane(pb, wp, T, w_prev.data(), packed.normals, 0.05, &pair);
    const Reference target_only = naive_plane(pb, wp, T, w_prev.data(), packed.normals, 0.05);
    const Output out = run(pb, wp, T, w_prev.data(), 1, &plane);
    CHECK(rel_diff(out.eval.H, ref.H) < 1e-12);
    CHECK(rel_diff(out.eval.g, ref.g) < 1e-11);
    CHECK(std::abs(out.eval.cost - ref.cost) < 1e-12 * ref.cost);
    CHECK(std::abs(out.eval.cost_prev_weights - ref.cost_prev) < 1e-12 * ref.cost_prev);
    CHECK(rel_diff(target_only.H, ref.H) > 1e-3);  // the pair normals made a difference
    const Output two = run(pb, wp, T, w_prev.data(), 2, &plane);
    CHECK(two.eval.H == out.eval.H);
    CHECK(two.eval.g == out.eval.g);
    // g against central differences of the fixed-weight cost (pair normals fixed).
    const Output at = run(pb, wp, T, nullptr, 1, &plane);
    auto cost = [&](const Vector6d& d) {
      return run(pb, wp, ppcr::se3::exp(d) * T, at.w.data(), 1, &plane).eval.cost_prev_weights;
    };
    const Vector6d g_num = central_gradient(cost);
    INFO("analytic " << at.eval.g.transpose() << "\nnumeric  " << g_num.transpose());
    CHECK(rel_diff(at.eval.g, g_num) < 1e-6);
  }
}

TEST_CASE("plane model without normals is the point model", "[normal_equations]") {
  const Problem pb = make_problem(68, 500, 6, 0.15);
  PackedPlane packed(pb, std::vector<Eigen::Vector3d>(pb.target.size(), Eigen::Vector3d::Zero()),
                     0.05);  // unused without normals: Omega = I
  ppcr::detail::PlaneModel& plane = packed.model;
  for (const WeightParams& wp : weight_params()) {
    const Output a = run(pb, wp, pb.T, nullptr, 1, &plane);
    const Output b = run(pb, wp, pb.T, nullptr, 1);
    CHECK(rel_diff(a.eval.H, b.eval.H) < 1e-12);
    CHECK(rel_diff(a.eval.g, b.eval.g) < 1e-11);
    CHECK(std::abs(a.eval.cost - b.eval.cost) < 1e-12 * b.eval.cost);
  }
}

TEST_CASE("normal_information equals the naive sum of w J^T n n^T J (I without a normal)",
          "[normal_equations]") {
  const Problem pb = make_problem(69, 400, 5, 0.15);
  const std::vector<Eigen::Vector3d> normals = random_normals(pb.target.size(), 70);
  Rng rng(71);
  std::vector<double> w(pb.source.size() * 5);
  for (double& v : w) v = core_test::uniform(rng, 0.0, 1.0);
  const std::size_t k = 5;
  Matrix6d ref = Matrix6d::Zero();
  for (std::size_t j = 0; j < pb.source.size(); ++j) {
    const Jacobian J = analytic_jacobian(pb.T * pb.source[j]);
    for (std::size_t m = 0; m < pb.assoc.count[j]; ++m) {
      const Eigen::Vector3d& n = normals[pb.assoc.index[j * k + m]];
      // A target point without a normal (zero) counts with Omega = I.
      const Eigen::Matrix3d nnT =
          n.squaredNorm() > 0.0 ? Eigen::Matrix3d(n * n.transpose()) : Eigen::Matrix3d::Identity();
      ref += w[j * k + m] * J.transpose() * nnT * J;
    }
  }
  ppcr::detail::Buffer<ppcr::detail::PlanePoint> points;
  ppcr::detail::pack_plane_points(pb.target, normals, 0.05, nullptr, &points);
  std::vector<Matrix6d> blocks;
  const Matrix6d got = NormalEquations::normal_information(pb.source, pb.assoc, pb.T, w.data(),
                                                           points, nullptr, &blocks);
  CHECK(rel_diff(got, ref) < 1e-12);
  // Summed in fixed blocks: the same to the bit on two threads.
  ppcr::detail::Parallel parallel(2);
  std::vector<Matrix6d> blocks2;
  const Matrix6d got2 = NormalEquations::normal_information(pb.source, pb.assoc, pb.T, w.data(),
                                                            points, &parallel, &blocks2);
  CHECK(got2 == got);
}

TEST_CASE("plane model: g from b - Omega p (PlanePoint) stays within rounding of |y|, far out",
          "[normal_equations]") {
  // The pass forms ebar_j = sum_k w Omega_k y_k - Obar_j p_j (PlanePoint) instead of
  // sum_k w Omega_k (y_k - p_j): each term rounds by about eps |y_k|, not eps |e_kj|. Shifted
  // 1e3 and 1e6 from the origin (|y| / |e| up to ~1e7; g's translation part then differs from
  // the naive reference by 2e-12 and 3e-9 relative, against 2e-15 unshifted), g must stay within
  // eps times sum w |Omega y| (translation) and sum w |Omega y| |p| (rotation) of the reference.
  // That is a margin, not a derived bound (the rounding of N terms grows like sqrt(N), the scale
  // like N): the differences measured 0.014-0.085 of it.
  for (double shift : {0.0, 1e3, 1e6}) {
    Problem pb = make_problem(72, 600, 6, 0.15);
    const Eigen::Vector3d o = shift * Eigen::Vector3d(0.6, -0.48, 0.64);
    for (Eigen::Vector3d& y : pb.target) y += o;
    pb.T = Eigen::Translation3d(o) * pb.T;
    PackedPlane packed(pb, 73, 0.05);
    const WeightParams wp{ppcr::WeightModel::kStudentT, 5.0, 1.0 / (0.05 * 0.05)};
    // A small motion about the shifted cloud (not about the origin, which would move it far):
    // the errors stay ~0.02-0.1 while |y| grows with the shift.
    const Eigen::Isometry3d T =
        Eigen::Translation3d(o) *
        core_test::make_pose(Eigen::Vector3d(1, 0, 1), 0.02, Eigen::Vector3d(0, 0.01, 0)) *
        Eigen::Translation3d(-o) * pb.T;
    const Reference ref = naive_plane(pb, wp, T, nullptr, packed.normals, 0.05);
    const Output out = run(pb, wp, T, nullptr, 1, &packed.model);
    const std::size_t k = static_cast<std::size_t>(pb.assoc.k);
    double scale_t = 0.0, scale_r = 0.0;
    for (std::size_t j = 0; j < pb.source.size(); ++j) {
      const double p_norm = (T * pb.source[j]).norm();
      for (std::size_t m = 0; m < pb.assoc.count[j]; ++m) {
        const std::uint32_t y = pb.assoc.index[j * k + m];
        const double term =
            ref.w[j * k + m] * (omega(packed.normals[y], 0.05) * pb.target[y]).norm();
        scale_t += term;
        scale_r += term * p_norm;
      }
    }
    const double eps = std::numeric_limits<double>::epsilon();
    INFO("shift " << shift << ": g " << out.eval.g.transpose() << "\nref " << ref.g.transpose());
    CHECK((out.eval.g.tail<3>() - ref.g.tail<3>()).cwiseAbs().maxCoeff() < eps * scale_t);
    CHECK((out.eval.g.head<3>() - ref.g.head<3>()).cwiseAbs().maxCoeff() < eps * scale_r);
    CHECK(rel_diff(out.eval.H, ref.H) < 1e-12);  // H has no such term
    CHECK(std::abs(out.eval.cost - ref.cost) < 1e-12 * ref.cost);
  }
}

TEST_CASE("pack_plane_points holds Omega = a I + n n^T and b = Omega y", "[normal_equations]") {
  const Problem pb = make_problem(74, 50, 6, 0.15);
  for (double epsilon : {0.05, 0.5}) {
    const PackedPlane packed(pb, 75, epsilon);  // every fifth point without a normal
    REQUIRE(packed.points.size() == pb.target.size());
    REQUIRE(packed.information.size() == pb.target.size());
    for (std::size_t i = 0; i < pb.target.size(); ++i) {
      const ppcr::detail::PlanePoint& q = packed.points[i];
      const ppcr::detail::PlaneInformation& o = packed.information[i];
      const Eigen::Matrix3d O = omega(packed.normals[i], epsilon);
      const Eigen::Vector3d b = O * pb.target[i];
      CHECK(q.y == pb.target[i]);
      CHECK(q.n == packed.normals[i]);
      CHECK(q.a == (packed.normals[i].squaredNorm() > 0.0 ? epsilon : 1.0));
      const Eigen::Matrix3d got =
          (Eigen::Matrix3d() << o.omega_xx_yy[0], o.omega_xy_yz[0], o.omega_xz_zz[0],
           o.omega_xy_yz[0], o.omega_xx_yy[1], o.omega_xy_yz[1], o.omega_xz_zz[0], o.omega_xy_yz[1],
           o.omega_xz_zz[1])
              .finished();
      CHECK((got - O).cwiseAbs().maxCoeff() < 1e-15);
      // Both forms of Omega y round differently (a y + n (n . y) against the product): 1e-12
      // still catches any misplaced lane.
      CHECK((Eigen::Vector3d(o.b_xy[0], o.b_xy[1], q.b_z) - b).cwiseAbs().maxCoeff() <
            1e-12 * (b.norm() + pb.target[i].norm()));
    }
    // Packed on two threads: the same records, to the bit.
    const ppcr::detail::Parallel parallel(2);
    ppcr::detail::Buffer<ppcr::detail::PlanePoint> points;
    ppcr::detail::Buffer<ppcr::detail::PlaneInformation> information;
    ppcr::detail::pack_plane_points(pb.target, packed.normals, epsilon, &parallel, &points,
                                    &information);
    REQUIRE(points.size() == pb.target.size());
    REQUIRE(information.size() == pb.target.size());
    for (std::size_t i = 0; i < pb.target.size(); ++i) {
      CHECK(std::memcmp(&points[i], &packed.points[i], sizeof(points[i])) == 0);
      CHECK(std::memcmp(&information[i], &packed.information[i], sizeof(information[i])) == 0);
    }
  }
}

// ------------------------------------------------------------------ four points at a time

namespace {

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

}  // namespace

TEST_CASE("pair normals four points at a time equal one point at a time, to the bit",
          "[normal_equations]") {
  // four_points.hpp: where the CPU has AVX, evaluate() takes runs of four points with the same
  // number of pairs in lanes. Against the one-point path (set_four_points(false)), with memcmp:
  // every output (H, g, costs, weights, squared errors, the pair normals' memo), for dyadic
  // powers (dof 1.25, 1.5, 3, 5) and others (dof 2.3: std::pow; Gaussian), without a memo,
  // filling it and reading it back at another pose, w_prev apart and in place, with and without
  // r_sq, rows left out, rows with more pairs than the path takes (k = 20 > 16), target and
  // source points without normals, rows whose errors all overflow, 1 and 2 threads.
  if (!ppcr::detail::four_lanes_available()) {
    WARN("four_points: this CPU has no AVX; only the one-point path runs here");
    return;
  }
  struct Case {
    int k;
    double radius;
  };
  for (const Case& cs : {Case{6, 0.17}, Case{10, 0.2}, Case{20, 0.3}}) {
    Problem pb = make_problem(201 + static_cast<std::uint64_t>(cs.k), 3000, cs.k, cs.radius);
    pb.assoc.left_out.assign(pb.source.size(), 0);
    for (std::size_t j = 0; j < pb.source.size(); j += 7) pb.assoc.left_out[j] = 1;
    pb.assoc.any_left_out = true;
    pb.assoc.recount();
    // Rows of every length, many runs of four alike (the path's) and many broken runs.
    std::size_t full = 0, partial = 0;
    for (std::size_t j = 0; j < pb.source.size(); ++j) {
      full += pb.assoc.count[j] == static_cast<std::size_t>(cs.k);
      partial += pb.assoc.count[j] > 0 && pb.assoc.count[j] < static_cast<std::size_t>(cs.k);
    }
    INFO("full " << full << " partial " << partial);
    REQUIRE(full > 100);
    REQUIRE(partial > 100);
    const EveryModel every(pb, 211);
    const ppcr::detail::PlaneModel* plane = every.models()[2];
    const std::size_t slots = pb.source.size() * static_cast<std::size_t>(cs.k);
    std::vector<WeightParams> params = {{ppcr::WeightModel::kStudentT, 1.25, 1.0 / (0.03 * 0.03)},
                                        {ppcr::WeightModel::kStudentT, 1.5, 1.0},
                                        {ppcr::WeightModel::kStudentT, 2.0, 1.0 / (0.1 * 0.1)},
                                        {ppcr::WeightModel::kStudentT, 3.0, 1.0 / (0.05 * 0.05)},
                                        {ppcr::WeightModel::kStudentT, 5.0, 1.0},
                                        {ppcr::WeightModel::kStudentT, 2.3, 1.0},
                                        {ppcr::WeightModel::kGaussian, 5.0, 1.0},
                                        {ppcr::WeightModel::kStudentT, 1.25, 1e308}};
    const Eigen::Isometry3d T_next =
        core_test::make_pose(Eigen::Vector3d(1, 0, 1), 0.02, Eigen::Vector3d(0, 0.01, 0)) * pb.T;
    for (const WeightParams& wp : params) {
      // 1e308: 3 off, a row's errors overflow where its nearest pair's r exceeds DBL_MAX / 1e308
      // = 1.8 (z_min = +inf; r is 0.05 |e|^2 + (n . e)^2 with |e| near 3); rows whose pairs'
      // normals lie across the shift do not, so runs of four mix both (checked below).
      const bool overflow = wp.inv_scale_sq > 1e300;
      Eigen::Isometry3d T = pb.T;
      if (overflow) T.pretranslate(Eigen::Vector3d(0.0, 0.0, 3.0));
      for (int threads : {1, 2}) {
        for (int memo_mode = 0; memo_mode < 2; ++memo_mode) {
          for (bool in_place : {false, true}) {
            Evaluation eval[2], next[2];
            std::vector<double> w[2], r_sq[2], memo[2], w_next[2];
            for (int four = 0; four < 2; ++four) {
              NormalEquations ne;
              ne.resize(pb.source.size(), cs.k);
              ne.set_four_points(four == 1);
              w[four] = every.w_prev;
              r_sq[four].assign(slots, -1.0);
              memo[four].assign(slots, -7.0);
              ppcr::detail::PairNormalMemo pm;
              if (memo_mode == 1) pm = {memo[four].data(), true};
              std::vector<double> separate(slots, 0.0);
              double* w_out = in_place ? w[four].data() : separate.data();
              ne.evaluate(pb.source, pb.target, pb.assoc, wp, T, w[four].data(), w_out,
                          in_place ? nullptr : r_sq[four].data(), core_test::parallel(threads),
                          &eval[four], plane, pm);
              if (!in_place) w[four] = separate;
              // The memo read back at another pose (a later pass of the same solve).
              w_next[four] = w[four];
              if (memo_mode == 1) pm.fill = false;
              ne.evaluate(pb.source, pb.target, pb.assoc, wp, T_next, w_next[four].data(),
                          w_next[four].data(), nullptr, core_test::parallel(threads), &next[four],
                          plane, pm);
            }
            INFO("k " << cs.k << " dof " << wp.dof << " gaussian "
                      << (wp.model == ppcr::WeightModel::kGaussian) << " inv_scale_sq "
                      << wp.inv_scale_sq << " threads " << threads << " memo " << memo_mode
                      << " in place " << in_place);
            for (const auto* e : {&eval, &next}) {
              CHECK(same_bits((*e)[0].H, (*e)[1].H));
              CHECK(same_bits((*e)[0].g, (*e)[1].g));
              CHECK(same_bits((*e)[0].cost, (*e)[1].cost));
              CHECK(same_bits((*e)[0].cost_prev_weights, (*e)[1].cost_prev_weights));
              CHECK(same_bits((*e)[0].weight_sum, (*e)[1].weight_sum));
            }
            CHECK(same_bits(w[0], w[1]));
            CHECK(same_bits(w_next[0], w_next[1]));
            CHECK(same_bits(r_sq[0], r_sq[1]));
            CHECK(same_bits(memo[0], memo[1]));
            CHECK(eval[0].weight_sum > 0.0);
            CHECK(!same_bits(w[0], w_next[0]));  // the second pass did move
            if (overflow) {  // rows overflowed (c = 0: every weight 0), and others did not
              std::size_t zero_rows = 0, weighted_rows = 0;
              for (std::size_t j = 0; j < pb.source.size(); ++j) {
                const std::size_t count = pb.assoc.count[j];
                if (count == 0 || pb.assoc.left_out[j] != 0) continue;
                const double* wj = &w[0][j * static_cast<std::size_t>(cs.k)];
                const bool all_zero =
                    std::all_of(wj, wj + count, [](double x) { return x == 0.0; });
                zero_rows += all_zero;
                weighted_rows += !all_zero;
              }
              CHECK(zero_rows > 50);
              CHECK(weighted_rows > 50);
            }
          }
        }
      }
    }
  }
}
