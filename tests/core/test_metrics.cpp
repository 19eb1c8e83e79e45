// Tests of ppcr/metrics.hpp: moments and the O(1) MSE between poses against brute force (in long
// double), the benchmark error against closed forms and a direct computation, and pose errors
// on known transforms.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core_test_util.hpp"
#include "ppcr/metrics.hpp"

using core_test::Rng;
using ppcr::PointCloud;

namespace {

using Vec3L = Eigen::Matrix<long double, 3, 1>;
using Mat3L = Eigen::Matrix<long double, 3, 3>;

// mean_i |A x_i - B x_i|^2 by brute force in long double.
long double brute_mse(const PointCloud& cloud, const Eigen::Isometry3d& A,
                      const Eigen::Isometry3d& B) {
  const Mat3L RA = A.linear().cast<long double>(), RB = B.linear().cast<long double>();
  const Vec3L tA = A.translation().cast<long double>(), tB = B.translation().cast<long double>();
  long double sum = 0.0L;
  for (const Eigen::Vector3d& x : cloud) {
    const Vec3L xl = x.cast<long double>();
    sum += ((RA * xl + tA) - (RB * xl + tB)).squaredNorm();
  }
  return sum / static_cast<long double>(cloud.size());
}

}  // namespace

TEST_CASE("compute_moments equals brute-force mean and covariance", "[metrics]") {
  Rng rng(81);
  for (double offset : {0.0, 1e3, 1e6}) {
    PointCloud cloud = core_test::uniform_cloud(rng, 3000, -2.0, 5.0);
    for (Eigen::Vector3d& p : cloud) p += Eigen::Vector3d(offset, -offset, 0.5 * offset);
    Vec3L sum = Vec3L::Zero();
    for (const Eigen::Vector3d& p : cloud) sum += p.cast<long double>();
    const Vec3L mean = sum / static_cast<long double>(cloud.size());
    Mat3L cov = Mat3L::Zero();
    for (const Eigen::Vector3d& p : cloud) {
      const Vec3L d = p.cast<long double>() - mean;
      cov += d * d.transpose();
    }
    cov /= static_cast<long double>(cloud.size());
    const ppcr::CloudMoments m = ppcr::compute_moments(cloud);
    INFO("offset " << offset);
    CHECK(m.count == cloud.size());
    CHECK((m.mean - mean.cast<double>()).norm() < 1e-12 * (1.0 + 2.0 * offset));
    CHECK((m.covariance - cov.cast<double>()).cwiseAbs().maxCoeff() <
          1e-10 * cov.cast<double>().cwiseAbs().maxCoeff());
  }
  const ppcr::CloudMoments empty = ppcr::compute_moments(PointCloud());
  CHECK(empty.count == 0u);
  CHECK(empty.mean == Eigen::Vector3d::Zero());
}

TEST_CASE("mse_between equals the brute-force mean of |A x - B x|^2", "[metrics]") {
  Rng rng(82);
  const PointCloud cloud = core_test::uniform_cloud(rng, 4000, -3.0, 2.0);
  const ppcr::CloudMoments m = ppcr::compute_moments(cloud);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Isometry3d A = core_test::make_pose(
        core_test::random_unit_vector(rng), core_test::uniform(rng, 0.0, 3.0),
        core_test::uniform(rng, 0.0, 2.0) * core_test::random_unit_vector(rng));
    // B near A (the case the termination criterion sees) or anywhere.
    const Eigen::Isometry3d B =
        i % 2 == 0 ? core_test::make_pose(core_test::random_unit_vector(rng), 1e-4,
                                          1e-4 * core_test::random_unit_vector(rng)) *
                         A
                   : core_test::make_pose(core_test::random_unit_vector(rng),
                                          core_test::uniform(rng, 0.0, 3.0),
                                          core_test::random_unit_vector(rng));
    const double ref = static_cast<double>(brute_mse(cloud, A, B));
    CHECK(ppcr::mse_between(m, A, B) == Approx(ref).epsilon(1e-10));
  }
  CHECK(ppcr::mse_between(m, Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()) == 0.0);
  CHECK(ppcr::mse_between(
            ppcr::CloudMoments(), Eigen::Isometry3d::Identity(),
            core_test::make_pose(Eigen::Vector3d(1, 0, 0), 1.0, Eigen::Vector3d(1, 1, 1))) == 0.0);
}

TEST_CASE("mse_between is accurate for a cloud 1e6 m from the origin", "[metrics]") {
  Rng rng(83);
  PointCloud cloud = core_test::uniform_cloud(rng, 3000, -20.0, 20.0);
  cloud[0] = Eigen::Vector3d(1e6, 0.0, 0.0);  // one point far away
  PointCloud far = core_test::uniform_cloud(rng, 3000, -20.0, 20.0);
  for (Eigen::Vector3d& p : far) p += Eigen::Vector3d(1e6, 2e6, -5e5);
  for (const PointCloud* c : {&cloud, &far}) {
    const ppcr::CloudMoments m = ppcr::compute_moments(*c);
    const Eigen::Vector3d centre = m.mean;
    for (int i = 0; i < 20; ++i) {
      // Small motions about the cloud (what successive registration poses differ by).
      const Eigen::Isometry3d A =
          core_test::make_pose(Eigen::Vector3d(0, 0, 1), 0.1, Eigen::Vector3d(1, 2, 3));
      const Eigen::Isometry3d about = core_test::make_pose(Eigen::Vector3d::UnitZ(), 0.0, centre);
      const Eigen::Isometry3d dB =
          about *
          core_test::make_pose(core_test::random_unit_vector(rng),
                               std::pow(10.0, core_test::uniform(rng, -6.0, -2.0)),
                               std::pow(10.0, core_test::uniform(rng, -5.0, -1.0)) *
                                   core_test::random_unit_vector(rng)) *
          about.inverse();
      const Eigen::Isometry3d B = dB * A;
      const double ref = static_cast<double>(brute_mse(*c, A, B));
      INFO("far " << (c == &far) << " ref " << ref);
      CHECK(ppcr::mse_between(m, A, B) == Approx(ref).epsilon(1e-6));
    }
  }
}

TEST_CASE("rotation_error_deg and translation_error on known transforms", "[metrics]") {
  Rng rng(84);
  for (double deg : {0.0, 1e-6, 0.01, 1.0, 10.0, 45.0, 90.0, 135.0, 179.0, 179.999}) {
    const Eigen::Isometry3d T_gt = core_test::make_pose(
        core_test::random_unit_vector(rng), core_test::uniform(rng, 0.0, 3.0),
        core_test::uniform(rng, 0.0, 5.0) * core_test::random_unit_vector(rng));
    const Eigen::Vector3d dt(0.3, -0.4, 1.2);  // |dt| = 1.3
    Eigen::Isometry3d T_est = T_gt;
    T_est.linear() = T_gt.linear() *
                     Eigen::AngleAxisd(core_test::deg2rad(deg), core_test::random_unit_vector(rng))
                         .toRotationMatrix();
    T_est.translation() += dt;
    INFO("deg " << deg);
    CHECK(ppcr::rotation_error_deg(T_est, T_gt) == Approx(deg).epsilon(1e-9).margin(1e-9));
    CHECK(ppcr::rotation_error_deg(T_gt, T_est) == Approx(deg).epsilon(1e-9).margin(1e-9));
    CHECK(ppcr::translation_error(T_est, T_gt) == Approx(1.3).epsilon(1e-14));
  }
  CHECK(ppcr::rotation_error_deg(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()) ==
        0.0);
}

TEST_CASE("benchmark_error: closed forms on symmetric clouds", "[metrics]") {
  // Points on a circle of radius rho about c, in the plane normal to the z axis, in +- pairs so
  // that the centroid is exactly c.
  const double rho = 2.0;
  const Eigen::Vector3d c(1.0, -2.0, 3.0);
  PointCloud circle;
  for (int i = 0; i < 36; ++i) {
    const double a = core_test::deg2rad(5.0 * i);
    const Eigen::Vector3d d(rho * std::cos(a), rho * std::sin(a), 0.0);
    circle.push_back(c + d);
    circle.push_back(c - d);
  }
  // Source in its own frame; T_gt maps it onto the circle.
  const Eigen::Isometry3d T_gt =
      core_test::make_pose(Eigen::Vector3d(1, 2, 3), 0.7, Eigen::Vector3d(-1, 0.5, 2));
  const PointCloud source = core_test::transformed(circle, T_gt.inverse());
  SECTION("a translation offset d: e = |d| / rho") {
    Eigen::Isometry3d T_est = T_gt;
    T_est.translation() += Eigen::Vector3d(0.03, 0.04, 0.0);  // |d| = 0.05
    CHECK(ppcr::benchmark_error(source, T_gt, T_est) == Approx(0.05 / rho).epsilon(1e-12));
  }
  SECTION("a rotation by theta about the circle's axis through c: e = 2 sin(theta / 2)") {
    const double theta = 0.3;
    const Eigen::Isometry3d about_c =
        core_test::make_pose(Eigen::Vector3d::UnitZ(), 0.0, c) *
        core_test::make_pose(Eigen::Vector3d::UnitZ(), theta, Eigen::Vector3d::Zero()) *
        core_test::make_pose(Eigen::Vector3d::UnitZ(), 0.0, -c);
    const Eigen::Isometry3d T_est = about_c * T_gt;
    CHECK(ppcr::benchmark_error(source, T_gt, T_est) ==
          Approx(2.0 * std::sin(theta / 2.0)).epsilon(1e-12));
  }
  SECTION("exact estimate: 0") { CHECK(ppcr::benchmark_error(source, T_gt, T_gt) < 1e-15); }
  CHECK(ppcr::benchmark_error(PointCloud(), T_gt, T_gt) == 0.0);
}

TEST_CASE("benchmark_error: point at the centroid exactly (identity ground truth) is skipped",
          "[metrics]") {
  PointCloud cloud = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, 2, 0),
                      Eigen::Vector3d(0, -2, 0), Eigen::Vector3d(0, 0, 0)};
  Eigen::Isometry3d T_est = Eigen::Isometry3d::Identity();
  T_est.translation() = Eigen::Vector3d(0, 0, 0.5);
  // Mean over the four non-centre points of 0.5 / |P|: (0.5 + 0.5 + 0.25 + 0.25) / 4.
  CHECK(ppcr::benchmark_error(cloud, Eigen::Isometry3d::Identity(), T_est) ==
        Approx(0.375).epsilon(1e-15));
}

TEST_CASE("benchmark_error equals a direct computation on a random cloud", "[metrics]") {
  Rng rng(85);
  const PointCloud source = core_test::uniform_cloud(rng, 2000, -1.0, 1.0);
  for (int i = 0; i < 10; ++i) {
    const Eigen::Isometry3d T_gt =
        core_test::make_pose(core_test::random_unit_vector(rng), core_test::uniform(rng, 0.0, 3.0),
                             core_test::random_unit_vector(rng));
    const Eigen::Isometry3d T_est =
        core_test::make_pose(core_test::random_unit_vector(rng), 0.05,
                             0.02 * core_test::random_unit_vector(rng)) *
        T_gt;
    long double cx = 0, cy = 0, cz = 0;
    for (const Eigen::Vector3d& x : source) {
      const Eigen::Vector3d p = T_gt * x;
      cx += p.x();
      cy += p.y();
      cz += p.z();
    }
    const long double n = static_cast<long double>(source.size());
    const Eigen::Vector3d c(static_cast<double>(cx / n), static_cast<double>(cy / n),
                            static_cast<double>(cz / n));
    long double sum = 0.0L;
    for (const Eigen::Vector3d& x : source) {
      sum += (T_gt * x - T_est * x).norm() / (T_gt * x - c).norm();
    }
    CHECK(ppcr::benchmark_error(source, T_gt, T_est) ==
          Approx(static_cast<double>(sum / n)).epsilon(1e-12));
  }
}
