// Tests of ppcr::se3 against independent references: Eigen::AngleAxisd for rotations, the
// general matrix exponential / logarithm (Eigen's unsupported MatrixFunctions) for SE(3),
// central differences for the left-update derivative, and the polar-decomposition property for
// orthonormalized().
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "core_test_util.hpp"
#include "ppcr/se3.hpp"

using core_test::kPi;
using core_test::Rng;
using ppcr::se3::Vector6d;

namespace {

Eigen::Matrix4d hat(const Vector6d& xi) {
  Eigen::Matrix4d X = Eigen::Matrix4d::Zero();
  // [w]_x written out by hand (not through ppcr::se3::skew).
  X(0, 1) = -xi(2);
  X(0, 2) = xi(1);
  X(1, 0) = xi(2);
  X(1, 2) = -xi(0);
  X(2, 0) = -xi(1);
  X(2, 1) = xi(0);
  X.block<3, 1>(0, 3) = xi.tail<3>();
  return X;
}

Vector6d random_twist(Rng& rng, double angle, double translation_scale) {
  Vector6d xi;
  xi.head<3>() = angle * core_test::random_unit_vector(rng);
  xi.tail<3>() = translation_scale * core_test::random_unit_vector(rng);
  return xi;
}

double max_abs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

}  // namespace

TEST_CASE("skew(w) * p equals the cross product", "[se3]") {
  Rng rng(1);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d w =
        core_test::uniform(rng, 0.1, 3.0) * core_test::random_unit_vector(rng);
    const Eigen::Vector3d p =
        core_test::uniform(rng, 0.1, 3.0) * core_test::random_unit_vector(rng);
    CHECK(max_abs(ppcr::se3::skew(w) * p - w.cross(p)) < 1e-14);
    CHECK(max_abs(ppcr::se3::skew(w) + ppcr::se3::skew(w).transpose()) == 0.0);
  }
}

TEST_CASE("exp_so3 matches Eigen::AngleAxisd for angles from 0 to pi", "[se3]") {
  Rng rng(2);
  std::vector<double> angles = {0.0,  1e-12, 1e-9, 1e-7, 1e-5, 9.999e-5,   1e-4,       1.0001e-4,
                                1e-3, 0.1,   1.0,  2.0,  3.0,  kPi - 1e-3, kPi - 1e-6, kPi};
  for (int i = 0; i < 200; ++i) angles.push_back(core_test::uniform(rng, 0.0, kPi));
  for (double a : angles) {
    const Eigen::Vector3d n = core_test::random_unit_vector(rng);
    const Eigen::Matrix3d R = ppcr::se3::exp_so3(a * n);
    const Eigen::Matrix3d R_ref = Eigen::AngleAxisd(a, n).toRotationMatrix();
    INFO("angle " << a);
    CHECK(max_abs(R - R_ref) < 1e-14);
    // The small off-diagonal (antisymmetric) part must be accurate RELATIVELY: it is what log
    // reads back. (R - R^T) / 2 = sin(a) [n]_x.
    if (a > 0.0 && a < 1.0) {
      const Eigen::Vector3d axis_sin(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
      CHECK((0.5 * axis_sin - std::sin(a) * n).norm() <= 1e-14 * std::sin(a));
    }
  }
}

TEST_CASE("exp_so3 of zero is exactly the identity", "[se3]") {
  CHECK(ppcr::se3::exp_so3(Eigen::Vector3d::Zero()) == Eigen::Matrix3d::Identity());
  const Eigen::Isometry3d T = ppcr::se3::exp(Vector6d::Zero());
  CHECK(T.matrix() == Eigen::Matrix4d::Identity());
  const Vector6d xi = ppcr::se3::log(Eigen::Isometry3d::Identity());
  CHECK(xi == Vector6d::Zero());
}

TEST_CASE("exp of a twist equals the 4x4 matrix exponential of its hat", "[se3]") {
  Rng rng(3);
  std::vector<double> angles = {0.0, 1e-12, 1e-8, 1e-5, 1e-4, 1e-3, kPi - 1e-3};
  for (int i = 0; i < 100; ++i) angles.push_back(core_test::uniform(rng, 0.0, kPi - 1e-3));
  for (double a : angles) {
    const Vector6d xi = random_twist(rng, a, core_test::uniform(rng, 0.0, 5.0));
    const Eigen::Matrix4d ref = hat(xi).exp();
    const Eigen::Matrix4d T = ppcr::se3::exp(xi).matrix();
    INFO("angle " << a << " twist " << xi.transpose());
    CHECK(max_abs(T - ref) < 1e-12 * (1.0 + xi.tail<3>().norm()));
    CHECK(T.row(3) == Eigen::RowVector4d(0, 0, 0, 1));
  }
}

TEST_CASE("log(exp(xi)) == xi on random twists with angles up to pi - 1e-3", "[se3]") {
  Rng rng(4);
  for (int i = 0; i < 500; ++i) {
    const double a = core_test::uniform(rng, 0.0, kPi - 1e-3);
    const Vector6d xi = random_twist(rng, a, core_test::uniform(rng, 0.0, 10.0));
    const Vector6d back = ppcr::se3::log(ppcr::se3::exp(xi));
    INFO("twist " << xi.transpose() << "\nlog    " << back.transpose());
    // log is well conditioned up to pi (its derivative, the inverse left Jacobian, stays
    // bounded), and log_so3 takes the axis from the symmetric part above pi/2, so the round
    // trip is accurate to a few ulps everywhere (measured <= 6e-16 relative).
    CHECK((back - xi).norm() < 1e-13 * (1.0 + xi.norm()));
  }
}

TEST_CASE("log(exp(xi)) == xi for small angles: rotation part (relative accuracy)", "[se3]") {
  Rng rng(5);
  for (double a :
       {0.0, 1e-15, 1e-12, 1e-10, 1e-8, 1e-6, 1e-5, 5e-5, 9.99e-5, 1e-4, 1.01e-4, 1e-3}) {
    for (int i = 0; i < 20; ++i) {
      const Vector6d xi = random_twist(rng, a, core_test::uniform(rng, 1e-6, 3.0));
      const Vector6d back = ppcr::se3::log(ppcr::se3::exp(xi));
      INFO("angle " << a << " twist " << xi.transpose() << "\nlog " << back.transpose());
      // Small angles must not be lost: the rotation part relative to its own size.
      CHECK((back.head<3>() - xi.head<3>()).norm() <= 1e-12 * a + 1e-300);
    }
  }
}

// Regression: B = (1 - cos a) / a^2 evaluated by the closed form from a = 1e-4 on carried a
// relative error ~1e-8 (1 - cos a cancels), which V v and V^{-1} t (D = (1 - A / (2B)) / a^2
// cancels again) turned into a relative translation error ~5e-9 near 1e-4 rad (~1e-11 at 1e-3).
// se3.cpp now uses B = 2 sin^2(a/2) / a^2 and Taylor series for C and D below 0.1 rad; the
// measured error is <= 4e-16 at every angle here, so 1e-13 leaves a 250x margin.
TEST_CASE("log(exp(xi)) == xi for small angles: translation part (relative accuracy)", "[se3]") {
  Rng rng(5);
  for (double a : {0.0, 1e-15, 1e-12, 1e-10, 1e-8, 1e-6, 1e-5, 5e-5, 9.99e-5, 1e-4, 1.01e-4, 3e-4,
                   1e-3, 1e-2}) {
    for (int i = 0; i < 20; ++i) {
      const Vector6d xi = random_twist(rng, a, core_test::uniform(rng, 1e-6, 3.0));
      const Vector6d back = ppcr::se3::log(ppcr::se3::exp(xi));
      INFO("angle " << a << " twist " << xi.transpose() << "\nlog " << back.transpose()
                    << "\nrelative translation error "
                    << (back.tail<3>() - xi.tail<3>()).norm() / xi.tail<3>().norm());
      CHECK((back.tail<3>() - xi.tail<3>()).norm() <= 1e-13 * xi.tail<3>().norm());
    }
  }
}

// Regression: for angles in [pi - 1e-4, pi) log_so3 took the axis from a column of (R + I) / 2,
// which still holds the antisymmetric part sin(a) [n]_x / 2: the axis was off by ~(pi - a) rad
// (1.7e-4 at pi - 9e-5, 2e-8 at pi - 1e-8). It now uses the exact symmetric part,
// (R + R^T) / 2 - cos(a) I = (1 - cos a) n n^T, for every angle above pi/2.
TEST_CASE("log(exp(xi)) == xi near pi (the axis-from-symmetric-part branch)", "[se3]") {
  // Angles above pi/2 take the axis from the symmetric part of R. log is well conditioned
  // below pi, so the axis must be exact to rounding: measured <= 9e-16, checked at 1e-13.
  Rng rng(6);
  for (double eps : {1e-3, 2e-4, 9e-5, 5e-5, 1e-5, 1e-6, 1e-8}) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d n = core_test::random_unit_vector(rng);
      const Eigen::Vector3d w = (kPi - eps) * n;
      const Eigen::Vector3d back = ppcr::se3::log_so3(ppcr::se3::exp_so3(w));
      INFO("pi - angle = " << eps << ", axis " << n.transpose() << ", log error "
                           << (back - w).norm());
      CHECK((back - w).norm() < 1e-13);
    }
  }
}

TEST_CASE("log_so3 at exactly pi returns angle pi and an axis that reproduces R", "[se3]") {
  Rng rng(7);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d n = core_test::random_unit_vector(rng);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(kPi, n).toRotationMatrix();
    const Eigen::Vector3d w = ppcr::se3::log_so3(R);
    CHECK(std::abs(w.norm() - kPi) < 1e-12);
    // +n and -n are both valid logs at pi.
    CHECK(std::min((w / w.norm() - n).norm(), (w / w.norm() + n).norm()) < 1e-7);
    CHECK(max_abs(Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() - R) < 1e-12);
  }
}

TEST_CASE("exp(log(T)) == T on random rigid transforms", "[se3]") {
  Rng rng(8);
  for (int i = 0; i < 300; ++i) {
    const double a = i < 20 ? kPi - 1e-3 * core_test::uniform(rng, 0.15, 1.0)
                            : core_test::uniform(rng, 0.0, kPi);
    const Eigen::Isometry3d T = core_test::make_pose(
        core_test::random_unit_vector(rng), a,
        core_test::uniform(rng, 0.0, 10.0) * core_test::random_unit_vector(rng));
    const Eigen::Isometry3d back = ppcr::se3::exp(ppcr::se3::log(T));
    INFO("angle " << a);
    CHECK(max_abs(back.matrix() - T.matrix()) < 1e-11);
  }
}

// Same regression as above (log_so3 near pi); at pi exactly either of the two logs +-pi n must
// reproduce T. Measured <= 9e-16 in both blocks.
TEST_CASE("exp(log(T)) == T near and at pi", "[se3]") {
  Rng rng(9);
  for (double eps : {1e-4, 5e-5, 1e-6, 1e-9, 0.0}) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Isometry3d T = core_test::make_pose(
          core_test::random_unit_vector(rng), kPi - eps, core_test::random_unit_vector(rng));
      const Eigen::Isometry3d back = ppcr::se3::exp(ppcr::se3::log(T));
      INFO("pi - angle = " << eps << ", error " << max_abs(back.matrix() - T.matrix()));
      CHECK(max_abs(back.linear() - T.linear()) < 1e-13);
      CHECK(max_abs(back.translation() - T.translation()) < 1e-13);
    }
  }
}

TEST_CASE("log of SE(3) matches the principal matrix logarithm", "[se3]") {
  Rng rng(10);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Isometry3d T = core_test::make_pose(
        core_test::random_unit_vector(rng), core_test::uniform(rng, 0.01, 3.0),
        core_test::uniform(rng, 0.0, 5.0) * core_test::random_unit_vector(rng));
    const Eigen::Matrix4d L = T.matrix().log();
    Vector6d ref;
    ref << L(2, 1), L(0, 2), L(1, 0), L(0, 3), L(1, 3), L(2, 3);
    CHECK((ppcr::se3::log(T) - ref).norm() < 1e-9);
  }
}

TEST_CASE("left-update derivative of exp(delta) * p at 0 is [ -[p]_x | I ]", "[se3]") {
  Rng rng(11);
  const double h = 1e-6;
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d p =
        core_test::uniform(rng, 0.1, 5.0) * core_test::random_unit_vector(rng);
    Eigen::Matrix<double, 3, 6> J_num;
    for (int c = 0; c < 6; ++c) {
      Vector6d d = Vector6d::Zero();
      d(c) = h;
      J_num.col(c) = (ppcr::se3::exp(d) * p - ppcr::se3::exp(-d) * p) / (2.0 * h);
    }
    Eigen::Matrix<double, 3, 6> J_ref;
    // -[p]_x written out by hand.
    J_ref << 0.0, p.z(), -p.y(), 1, 0, 0,  //
        -p.z(), 0.0, p.x(), 0, 1, 0,       //
        p.y(), -p.x(), 0.0, 0, 0, 1;
    INFO("numeric\n" << J_num << "\nexpected\n" << J_ref);
    CHECK(max_abs(J_num - J_ref) < 1e-8 * (1.0 + p.norm()));
  }
}

TEST_CASE("is_rigid accepts rotations and rejects everything else", "[se3]") {
  Rng rng(12);
  const Eigen::Matrix4d good =
      core_test::make_pose(core_test::random_unit_vector(rng), 1.2, Eigen::Vector3d(1, -2, 3))
          .matrix();
  CHECK(ppcr::se3::is_rigid(good));
  CHECK(ppcr::se3::is_rigid(Eigen::Matrix4d::Identity()));
  CHECK(ppcr::se3::is_rigid(Eigen::Matrix4d::Identity(), 0.0));

  SECTION("a perturbation within the tolerance is accepted") {
    Eigen::Matrix4d m = good;
    m(0, 1) += 1e-8;
    CHECK(ppcr::se3::is_rigid(m, 1e-6));
    CHECK_FALSE(ppcr::se3::is_rigid(m, 1e-10));
  }
  SECTION("scaled") {
    Eigen::Matrix4d m = good;
    m.topLeftCorner<3, 3>() *= 1.001;
    CHECK_FALSE(ppcr::se3::is_rigid(m));
  }
  SECTION("uniformly scaled by -1 (det -1)") {
    Eigen::Matrix4d m = good;
    m.topLeftCorner<3, 3>() *= -1.0;
    CHECK_FALSE(ppcr::se3::is_rigid(m));
  }
  SECTION("sheared") {
    Eigen::Matrix4d m = good;
    Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
    S(0, 1) = 0.01;
    m.topLeftCorner<3, 3>() = m.topLeftCorner<3, 3>() * S;
    CHECK_FALSE(ppcr::se3::is_rigid(m));
  }
  SECTION("reflection: orthogonal with det -1") {
    Eigen::Matrix4d m = good;
    m.col(2).head<3>() *= -1.0;
    CHECK(std::abs(m.topLeftCorner<3, 3>().determinant() + 1.0) < 1e-12);
    CHECK_FALSE(ppcr::se3::is_rigid(m));
  }
  SECTION("bad last row") {
    for (int c = 0; c < 4; ++c) {
      Eigen::Matrix4d m = good;
      m(3, c) += 0.5;
      CHECK_FALSE(ppcr::se3::is_rigid(m));
    }
  }
  SECTION("NaN or Inf anywhere") {
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        Eigen::Matrix4d m = good;
        m(r, c) = std::numeric_limits<double>::quiet_NaN();
        CHECK_FALSE(ppcr::se3::is_rigid(m));
        m(r, c) = std::numeric_limits<double>::infinity();
        CHECK_FALSE(ppcr::se3::is_rigid(m));
      }
    }
  }
}

TEST_CASE("orthonormalized returns the nearest rotation (polar factor), det +1", "[se3]") {
  Rng rng(13);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Isometry3d T =
        core_test::make_pose(core_test::random_unit_vector(rng), core_test::uniform(rng, 0.0, kPi),
                             Eigen::Vector3d(1.5, -2.5, 0.25));
    Eigen::Isometry3d P = T;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) P.linear()(r, c) += core_test::gaussian(rng, 1e-3);
    }
    const Eigen::Isometry3d O = ppcr::se3::orthonormalized(P);
    const Eigen::Matrix3d R = O.linear();
    CHECK(max_abs(R.transpose() * R - Eigen::Matrix3d::Identity()) < 1e-14);
    CHECK(std::abs(R.determinant() - 1.0) < 1e-14);
    CHECK(ppcr::se3::is_rigid(O.matrix(), 1e-12));
    CHECK(O.translation() == P.translation());
    // Polar decomposition M = R S with S symmetric positive definite: R^T M is symmetric.
    const Eigen::Matrix3d S = R.transpose() * P.linear();
    CHECK(max_abs(S - S.transpose()) < 1e-14);
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(0.5 * (S + S.transpose()))
              .eigenvalues()
              .minCoeff() > 0.0);
    // Close to the rotation it was perturbed from.
    CHECK(max_abs(R - T.linear()) < 1e-2);
  }
}

TEST_CASE("orthonormalized keeps det +1 for a reflected input", "[se3]") {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal();
  T.linear() *= Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Isometry3d O = ppcr::se3::orthonormalized(T);
  CHECK(std::abs(O.linear().determinant() - 1.0) < 1e-12);
  CHECK(ppcr::se3::is_rigid(O.matrix(), 1e-12));
}

TEST_CASE("orthonormalized leaves an exact rotation unchanged", "[se3]") {
  const Eigen::Isometry3d T =
      core_test::make_pose(Eigen::Vector3d(0.3, -1, 2), 2.5, Eigen::Vector3d(4, 5, 6));
  CHECK(max_abs(ppcr::se3::orthonormalized(T).matrix() - T.matrix()) < 1e-15);
}

TEST_CASE("rotation_angle is accurate near 0 and near pi", "[se3]") {
  Rng rng(14);
  std::vector<double> angles = {0.0, 1e-15, 1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 0.5, 1.5, 3.0};
  for (double eps : {1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 0.0}) angles.push_back(kPi - eps);
  for (double a : angles) {
    for (int i = 0; i < 10; ++i) {
      const Eigen::Matrix3d R =
          Eigen::AngleAxisd(a, core_test::random_unit_vector(rng)).toRotationMatrix();
      const double got = ppcr::se3::rotation_angle(R);
      INFO("angle " << a << " got " << got);
      CHECK(got >= 0.0);
      CHECK(got <= kPi);
      // Relative near 0 (acos would lose everything below ~1e-8), absolute near pi.
      if (a < 1e-3) {
        CHECK(std::abs(got - a) <= 1e-10 * a + 1e-300);
      } else {
        CHECK(std::abs(got - a) < 1e-14);
      }
    }
  }
}
