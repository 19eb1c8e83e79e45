// Tests of PoseAcceleration (Anderson acceleration of the outer loop's pose) on maps whose fixed
// point is known by construction: a scalar contraction toward a pose (the secant step lands on
// it, in the chart of a pose that is not the identity), an affine contraction of the twist
// (against the fixed point and against plain iteration), and the safeguards (the gain bound, the
// restart on a growing step, reset()).
#include <catch2/catch.hpp>
#include <cmath>

#include "core_test_util.hpp"
#include "ppcr/se3.hpp"
#include "registration/pose_acceleration.hpp"

using ppcr::detail::PoseAcceleration;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

namespace {

// Distance between poses as the acceleration measures it: the twist of A B^-1, rotation scaled
// by `length`.
double distance(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B, double length) {
  Vector6d xi = ppcr::se3::log(A * B.inverse());
  xi.head<3>() *= length;
  return xi.norm();
}

// G(T) = exp(xi* + M (log T - xi*)): the fixed point exp(xi*), the chart anchored at identity.
struct AffineMap {
  Vector6d fixed;
  Matrix6d M;
  Eigen::Isometry3d operator()(const Eigen::Isometry3d& T) const {
    return ppcr::se3::exp(fixed + M * (ppcr::se3::log(T) - fixed));
  }
};

Vector6d some_twist() {
  Vector6d xi;
  xi << 0.05, -0.08, 0.12, 0.3, -0.2, 0.1;  // about 8 degrees and 0.37 length units
  return xi;
}

}  // namespace

TEST_CASE("memory 0 returns the iteration's own pose") {
  PoseAcceleration off(0, 1.0, 10.0);
  const AffineMap G{some_twist(), 0.9 * Matrix6d::Identity()};
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 5; ++i) {
    const Eigen::Isometry3d g = G(x);
    const Eigen::Isometry3d next = off.next(x, g);
    REQUIRE(next.matrix() == g.matrix());
    x = next;
  }
}

TEST_CASE("memory 1 on a scalar contraction takes the secant step onto the fixed point") {
  // In the chart of A (twists of T A^-1), G(x) = x* + rho (x - x*): after one plain step the
  // secant through (x0, f0), (x1, f1) hits f = 0 at x*, a jump of rho / (1 - rho) = 4 last steps,
  // within the bound of 10. Starting at A makes A the acceleration's anchor: a chart and its
  // inverse that disagree (A^-1 T against T A^-1) miss x*.
  const double length = 1.7;
  PoseAcceleration acceleration(1, length, 10.0);
  Vector6d a_twist;
  a_twist << -0.4, 0.3, 0.9, 1.0, 2.0, -0.5;
  const Eigen::Isometry3d A = ppcr::se3::exp(a_twist);
  const double rho = 0.8;
  auto G = [&](const Eigen::Isometry3d& T) {
    return ppcr::se3::exp(rho * ppcr::se3::log(T * A.inverse()) + (1.0 - rho) * some_twist()) * A;
  };
  const Eigen::Isometry3d star = ppcr::se3::exp(some_twist()) * A;
  REQUIRE(distance(G(star), star, length) < 1e-12);
  const Eigen::Isometry3d x0 = A;
  const Eigen::Isometry3d x1 = acceleration.next(x0, G(x0));
  CHECK(x1.matrix() == G(x0).matrix());  // no history yet: the plain step
  const Eigen::Isometry3d x2 = acceleration.next(x1, G(x1));
  INFO("plain step's distance " << distance(G(x1), star, length));
  CHECK(distance(x2, star, length) < 1e-12);
  CHECK(distance(G(x1), star, length) > 0.1);
}

TEST_CASE("the extrapolation is bounded by max_gain last steps") {
  // rho = 0.95: the secant jump would be 19 last steps; the bound keeps it to 10, along the line
  // from G(x1) toward the fixed point.
  const double length = 0.6, gain = 10.0;
  PoseAcceleration acceleration(1, length, gain);
  const AffineMap G{some_twist(), 0.95 * Matrix6d::Identity()};
  const Eigen::Isometry3d star = ppcr::se3::exp(some_twist());
  const Eigen::Isometry3d x0 = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d x1 = acceleration.next(x0, G(x0));
  const Eigen::Isometry3d g1 = G(x1);
  const Eigen::Isometry3d x2 = acceleration.next(x1, g1);
  const double step = distance(g1, x1, length);
  CHECK(distance(x2, g1, length) == Approx(gain * step).epsilon(1e-9));
  CHECK(distance(x2, star, length) ==
        Approx(distance(g1, star, length) - gain * step).epsilon(1e-9));
}

TEST_CASE("on an affine contraction it reaches the fixed point long before plain iteration") {
  core_test::Rng rng(5);
  Matrix6d Q;
  for (int i = 0; i < 36; ++i) Q(i / 6, i % 6) = core_test::uniform(rng, -1.0, 1.0);
  Q = Eigen::HouseholderQR<Matrix6d>(Q).householderQ();  // a random rotation of the axes
  Vector6d rates;
  rates << 0.97, 0.9, 0.7, 0.5, 0.3, 0.1;  // one slow direction, as in a creep
  const AffineMap G{some_twist(), Q * rates.asDiagonal() * Q.transpose()};
  // exp(xi*) is G's fixed point: xi = xi* + M (xi - xi*) holds at xi = xi*.
  REQUIRE(
      (G(ppcr::se3::exp(some_twist())).matrix() - ppcr::se3::exp(some_twist()).matrix()).norm() <
      1e-12);
  const Eigen::Isometry3d star = ppcr::se3::exp(some_twist());
  const double length = 1.0;
  PoseAcceleration acceleration(6, length, 1e6);
  Eigen::Isometry3d x = Eigen::Isometry3d::Identity(), plain = x;
  for (int i = 0; i < 12; ++i) {
    x = acceleration.next(x, G(x));
    plain = G(plain);
  }
  const double start = distance(Eigen::Isometry3d::Identity(), star, length);
  INFO("start " << start << ", plain " << distance(plain, star, length) << ", accelerated "
                << distance(x, star, length));
  CHECK(distance(plain, star, length) > 0.05 * start);  // 0.97^12 of the slow part is left
  CHECK(distance(x, star, length) < 1e-8 * start);
}

TEST_CASE("a growing step restarts the history") {
  // An expanding map: the step grows, so the second call restarts and returns the plain pose.
  const double length = 1.0;
  PoseAcceleration acceleration(3, length, 10.0);
  const AffineMap expanding{some_twist(), 1.5 * Matrix6d::Identity()};
  const Eigen::Isometry3d x0 = ppcr::se3::exp(0.9 * some_twist());
  const Eigen::Isometry3d x1 = acceleration.next(x0, expanding(x0));
  const Eigen::Isometry3d x2 = acceleration.next(x1, expanding(x1));
  CHECK(x2.matrix() == expanding(x1).matrix());
}

TEST_CASE("reset() forgets the history") {
  // Two steps of one contraction leave a history; after reset() the first step of another map
  // is the plain one. Without the reset it would be extrapolated: its step (0.03 |xi*|) is
  // shorter than the last (0.16 |xi*|), so no restart would hide the history.
  const double length = 1.0;
  PoseAcceleration acceleration(3, length, 10.0);
  const AffineMap G{some_twist(), 0.8 * Matrix6d::Identity()};
  const Eigen::Isometry3d x0 = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d x1 = acceleration.next(x0, G(x0));
  acceleration.next(x1, G(x1));
  acceleration.reset();
  const AffineMap H{0.5 * some_twist(), 0.9 * Matrix6d::Identity()};
  CHECK(acceleration.next(x1, H(x1)).matrix() == H(x1).matrix());
}
