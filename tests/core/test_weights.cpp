// Tests of ppcr::compute_weights (the E-step, paper eq. 2-4) against closed forms computed by
// hand, direct (non-log-space) evaluation on moderate values, and limits.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

#include "core_test_util.hpp"
#include "model/e_step.hpp"
#include "model/e_step_kernel.hpp"

using core_test::Rng;
using ppcr::compute_weights;
using ppcr::WeightModel;

namespace {

std::vector<double> weights_of(WeightModel model, double dof, double inv_scale_sq,
                               const std::vector<double>& r, double* lse = nullptr) {
  std::vector<double> w(r.size(), -1.0);
  const double l = compute_weights(model, dof, inv_scale_sq, r.data(), r.size(), w.data());
  if (lse != nullptr) *lse = l;
  return w;
}

double rel_err(double got, double want) {
  return std::abs(got - want) / std::max(std::abs(want), 1e-300);
}

}  // namespace

TEST_CASE("Student-t, two neighbours at r = 0 and r = nu: closed form", "[weights]") {
  for (double nu : {1.0, 3.0, 5.0, 9.0, 0.5}) {
    // p_2 / p_1 = (1 + nu/nu)^(-(nu+3)/2) = 2^(-(nu+3)/2).
    const double q = std::pow(2.0, -(nu + 3.0) / 2.0);
    const double pi1 = 1.0 / (1.0 + q), pi2 = q / (1.0 + q);
    const double w1 = pi1 * (nu + 3.0) / nu;         // z = 0
    const double w2 = pi2 * (nu + 3.0) / (nu + nu);  // z = nu
    double lse = 0.0;
    const std::vector<double> w = weights_of(WeightModel::kStudentT, nu, 1.0, {0.0, nu}, &lse);
    INFO("nu " << nu);
    CHECK(rel_err(w[0], w1) < 1e-14);
    CHECK(rel_err(w[1], w2) < 1e-14);
    // log(p_1 + p_2) with p_1 = 1.
    CHECK(std::abs(lse - std::log1p(q)) < 1e-15);
  }
  // nu = 5 by hand: q = 2^-4 = 1/16, pi = (16/17, 1/17), w = (16/17 * 8/5, 1/17 * 8/10).
  const std::vector<double> w = weights_of(WeightModel::kStudentT, 5.0, 1.0, {0.0, 5.0});
  CHECK(rel_err(w[0], 16.0 / 17.0 * 1.6) < 1e-15);
  CHECK(rel_err(w[1], 1.0 / 17.0 * 0.8) < 1e-15);
  // The order of the neighbours does not matter.
  const std::vector<double> w_rev = weights_of(WeightModel::kStudentT, 5.0, 1.0, {5.0, 0.0});
  CHECK(w_rev[0] == w[1]);
  CHECK(w_rev[1] == w[0]);
}

TEST_CASE("One neighbour: posterior 1, Student-t w = (nu+3)/(nu+z), Gaussian w = 1", "[weights]") {
  Rng rng(21);
  for (int i = 0; i < 200; ++i) {
    const double nu = core_test::uniform(rng, 0.2, 50.0);
    const double r = i == 0 ? 0.0 : std::pow(10.0, core_test::uniform(rng, -8.0, 6.0));
    const double s = std::pow(10.0, core_test::uniform(rng, -3.0, 3.0));
    const double z = r / (s * s);
    double lse = 0.0;
    const std::vector<double> wt = weights_of(WeightModel::kStudentT, nu, 1.0 / (s * s), {r}, &lse);
    INFO("nu " << nu << " r " << r << " s " << s);
    CHECK(rel_err(wt[0], (nu + 3.0) / (nu + z)) < 1e-13);
    CHECK(std::abs(lse - (-(nu + 3.0) / 2.0 * std::log(1.0 + z / nu))) <=
          1e-12 * (1.0 + std::abs(lse)));
    const std::vector<double> wg = weights_of(WeightModel::kGaussian, nu, 1.0 / (s * s), {r}, &lse);
    CHECK(wg[0] == 1.0);
    CHECK(rel_err(lse, -z / 2.0) < 1e-13);
  }
}

TEST_CASE("Gaussian weights equal a direct softmax of -r/2 on moderate values", "[weights]") {
  Rng rng(22);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t n = 1 + static_cast<std::size_t>(trial % 25);
    std::vector<double> r(n);
    for (double& v : r) v = core_test::uniform(rng, 0.0, 30.0);
    double sum = 0.0;
    for (double v : r) sum += std::exp(-v / 2.0);
    double lse = 0.0;
    const std::vector<double> w = weights_of(WeightModel::kGaussian, 5.0, 1.0, r, &lse);
    for (std::size_t k = 0; k < n; ++k) {
      CHECK(rel_err(w[k], std::exp(-r[k] / 2.0) / sum) < 1e-13);
    }
    CHECK(std::abs(lse - std::log(sum)) < 1e-13);
    CHECK(std::abs(std::accumulate(w.begin(), w.end(), 0.0) - 1.0) < 1e-14);
  }
}

TEST_CASE("Student-t weights equal a direct evaluation of eq. 3-4 on moderate values",
          "[weights]") {
  Rng rng(23);
  // Each kernel: nu 5 (q^4 by squaring), multiples of 0.25 (square roots and squaring), any other
  // nu (std::pow); the reference always uses std::pow.
  const double kKernelDof[] = {5.0, 1.0, 2.0, 0.25, 0.75, 1.25, 1.5, 1.75, 2.25, 3.5, 29.0, 61.0};
  for (int trial = 0; trial < 248; ++trial) {
    const std::size_t n = 1 + static_cast<std::size_t>(trial % 25);
    const double nu = trial < 48 ? kKernelDof[trial % 12] : core_test::uniform(rng, 0.5, 30.0);
    const double s = core_test::uniform(rng, 0.1, 2.0);
    std::vector<double> r(n);
    for (double& v : r) v = core_test::uniform(rng, 0.0, 10.0) * s * s;
    std::vector<double> p(n);
    for (std::size_t k = 0; k < n; ++k) {
      p[k] = std::pow(1.0 + r[k] / (s * s) / nu, -(nu + 3.0) / 2.0);
    }
    const double sum = std::accumulate(p.begin(), p.end(), 0.0);
    double lse = 0.0;
    const std::vector<double> w = weights_of(WeightModel::kStudentT, nu, 1.0 / (s * s), r, &lse);
    double posterior_sum = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      const double z = r[k] / (s * s);
      INFO("nu " << nu << " k " << k << " z " << z);
      CHECK(rel_err(w[k], p[k] / sum * (nu + 3.0) / (nu + z)) < 1e-12);
      posterior_sum += w[k] * (nu + z) / (nu + 3.0);  // w / expected precision = posterior
    }
    CHECK(std::abs(posterior_sum - 1.0) < 1e-14);
    CHECK(std::abs(lse - std::log(sum)) < 1e-12 * (1.0 + std::abs(lse)));
  }
}

TEST_CASE("Gaussian limit: Student-t with dof 1e7 matches the Gaussian", "[weights]") {
  Rng rng(24);
  for (int trial = 0; trial < 100; ++trial) {
    const std::size_t n = 1 + static_cast<std::size_t>(trial % 20);
    std::vector<double> r(n);
    for (double& v : r) v = core_test::uniform(rng, 0.0, 9.0);
    const std::vector<double> wt = weights_of(WeightModel::kStudentT, 1e7, 1.0, r);
    const std::vector<double> wg = weights_of(WeightModel::kGaussian, 1e7, 1.0, r);
    for (std::size_t k = 0; k < n; ++k) {
      const double pt = wt[k] * (1e7 + r[k]) / (1e7 + 3.0);  // Student-t posterior
      CHECK(std::abs(pt - wg[k]) < 1e-5);
      CHECK(std::abs(wt[k] - wg[k]) < 1e-5);
    }
  }
}

TEST_CASE("inv_scale_sq: the weights of (r, s) equal those of (r / s^2, 1)", "[weights]") {
  Rng rng(25);
  for (WeightModel model : {WeightModel::kStudentT, WeightModel::kGaussian}) {
    for (int trial = 0; trial < 50; ++trial) {
      const std::size_t n = 1 + static_cast<std::size_t>(trial % 12);
      // A power-of-two scale makes r / s^2 exact, so the results must be bit-identical.
      const double s = std::ldexp(1.0, static_cast<int>(trial % 9) - 4);
      const double s_any = core_test::uniform(rng, 0.01, 100.0);
      std::vector<double> r(n), r_scaled(n), r_scaled_any(n);
      for (std::size_t k = 0; k < n; ++k) {
        r[k] = core_test::uniform(rng, 0.0, 6.0) * s * s;
        r_scaled[k] = r[k] / (s * s);
      }
      double lse_a = 0.0, lse_b = 0.0;
      const std::vector<double> a = weights_of(model, 5.0, 1.0 / (s * s), r, &lse_a);
      const std::vector<double> b = weights_of(model, 5.0, 1.0, r_scaled, &lse_b);
      CHECK(a == b);
      CHECK(lse_a == lse_b);
      // Any scale: equal to rounding.
      for (std::size_t k = 0; k < n; ++k) {
        r[k] = core_test::uniform(rng, 0.0, 6.0) * s_any * s_any;
        r_scaled_any[k] = r[k] / (s_any * s_any);
      }
      const std::vector<double> c = weights_of(model, 5.0, 1.0 / (s_any * s_any), r);
      const std::vector<double> d = weights_of(model, 5.0, 1.0, r_scaled_any);
      for (std::size_t k = 0; k < n; ++k) CHECK(rel_err(c[k], d[k]) < 1e-12);
    }
  }
}

TEST_CASE("Huge errors: finite weights, closest posterior >= 1/n, not all zero", "[weights]") {
  const std::vector<std::vector<double>> cases = {
      {1e12},
      {1e300},
      {1e12, 1e12, 1e12},
      {1e300, 1e300},
      {1e300, 1e12, 1.0, 1e-3},
      {1e12, 1e12 + 1e6, 2e12},
      {1e300, 1e299, 1e298, 1e150, 1e100},
      {1e305, 1e306, 1e307},
      {0.0, 1e300},
  };
  for (WeightModel model : {WeightModel::kStudentT, WeightModel::kGaussian}) {
    for (const std::vector<double>& r : cases) {
      for (double inv_s2 : {1.0, 4.0, 1e-4}) {
        double lse = 0.0;
        const std::vector<double> w = weights_of(model, 5.0, inv_s2, r, &lse);
        const std::size_t n = r.size();
        std::size_t closest = 0;
        for (std::size_t k = 1; k < n; ++k) {
          if (r[k] < r[closest]) closest = k;
        }
        INFO("model " << static_cast<int>(model) << " r[0] " << r[0] << " n " << n << " inv_s2 "
                      << inv_s2);
        CHECK(std::isfinite(lse));
        double posterior_sum = 0.0;
        for (std::size_t k = 0; k < n; ++k) {
          CHECK(std::isfinite(w[k]));
          CHECK(w[k] >= 0.0);
          const double z = r[k] * inv_s2;
          const double posterior =
              model == WeightModel::kGaussian ? w[k] : w[k] * ((5.0 + z) / 8.0);
          if (k == closest) CHECK(posterior >= 1.0 / static_cast<double>(n) * (1.0 - 1e-15));
          posterior_sum += posterior;
        }
        CHECK(std::abs(posterior_sum - 1.0) < 1e-12);
        CHECK(w[closest] > 0.0);
      }
    }
  }
}

TEST_CASE("Equal errors give equal posteriors 1/n", "[weights]") {
  for (std::size_t n : {1u, 2u, 7u, 20u, 1024u}) {
    for (double r : {0.0, 0.3, 1e6}) {
      const std::vector<double> rr(n, r);
      const std::vector<double> wg = weights_of(WeightModel::kGaussian, 5.0, 1.0, rr);
      const std::vector<double> wt = weights_of(WeightModel::kStudentT, 5.0, 1.0, rr);
      for (std::size_t k = 0; k < n; ++k) {
        CHECK(rel_err(wg[k], 1.0 / static_cast<double>(n)) < 1e-13);
        CHECK(rel_err(wt[k], 1.0 / static_cast<double>(n) * 8.0 / (5.0 + r)) < 1e-13);
      }
    }
  }
}

TEST_CASE("Posteriors sum to one on random inputs, and decrease with the error", "[weights]") {
  Rng rng(26);
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t n = 1 + static_cast<std::size_t>(trial % 30);
    const double nu = core_test::uniform(rng, 0.3, 20.0);
    const double inv_s2 = std::pow(10.0, core_test::uniform(rng, -4.0, 4.0));
    std::vector<double> r(n);
    for (double& v : r) v = std::pow(10.0, core_test::uniform(rng, -6.0, 4.0));
    const std::vector<double> wg = weights_of(WeightModel::kGaussian, nu, inv_s2, r);
    const std::vector<double> wt = weights_of(WeightModel::kStudentT, nu, inv_s2, r);
    double sg = 0.0, st = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      sg += wg[k];
      st += wt[k] * (nu + r[k] * inv_s2) / (nu + 3.0);
    }
    CHECK(std::abs(sg - 1.0) < 1e-13);
    CHECK(std::abs(st - 1.0) < 1e-13);
    // Both the posterior and the weight are non-increasing in r.
    for (std::size_t a = 0; a < n; ++a) {
      for (std::size_t b = 0; b < n; ++b) {
        if (r[a] < r[b]) {
          CHECK(wg[a] >= wg[b]);
          CHECK(wt[a] >= wt[b]);
        }
      }
    }
  }
}

// z = r / s^2 overflows to +inf for a tiny s (e.g. r = 1e300, 1 / s^2 = 1e10). The ratio form
// then met inf / inf and gave NaN weights. Now a neighbour with z = inf next to a finite one gets
// weight 0; when every z of the point overflows, the Student-t weights are all 0 (each is below
// (nu + 3) / DBL_MAX) and the Gaussian weights are the posteriors of the exact z = r / s^2.
TEST_CASE("Overflowing z = r / s^2: weights stay finite", "[weights]") {
  const double inf = std::numeric_limits<double>::infinity();
  for (WeightModel model : {WeightModel::kStudentT, WeightModel::kGaussian}) {
    for (double nu : {5.0, 2.0, 2.7}) {  // the three kernels: q^4, q^2.5 by squaring, exp(e log q)
      double lse = 0.0;
      const std::vector<double> w = weights_of(model, nu, 1e10, {1e300, 2e300}, &lse);
      INFO("model " << static_cast<int>(model) << " nu " << nu << " w " << w[0] << " " << w[1]);
      CHECK(std::isfinite(w[0]));
      CHECK(std::isfinite(w[1]));
      CHECK(w[0] >= w[1]);
      if (model == WeightModel::kStudentT) {
        CHECK(w[0] == 0.0);
        CHECK(w[1] == 0.0);
        // log p_1 + log(1 + p_2 / p_1) with log p_k = -(nu+3)/2 log(z_k / nu), p_2 / p_1 = 2^-e.
        const double e = (nu + 3.0) / 2.0;
        const double want =
            -e * (std::log(1e300) + std::log(1e10) - std::log(nu)) + std::log1p(std::pow(2.0, -e));
        CHECK(std::abs(lse - want) < 1e-12 * std::abs(want));
      } else {
        // z_2 - z_1 = 1e310: the closest neighbour takes the whole posterior.
        CHECK(w[0] == 1.0);
        CHECK(w[1] == 0.0);
        CHECK(lse == -inf);  // -z_1 / 2 = -5e309
      }
      // Differences of z that fit: Gaussian posteriors of the exact z.
      const std::vector<double> g = weights_of(model, nu, 1e10, {1e300, 1e300 + 1e285});
      if (model == WeightModel::kGaussian) {
        const double ratio = std::exp(-0.5 * ((1e300 + 1e285) - 1e300) * 1e10);
        CHECK(rel_err(g[0], 1.0 / (1.0 + ratio)) < 1e-14);
        CHECK(rel_err(g[1], ratio / (1.0 + ratio)) < 1e-14);
      } else {
        CHECK(g[0] == 0.0);
        CHECK(g[1] == 0.0);
      }
      // One finite z beside infinite ones: the infinite ones get weight 0.
      const std::vector<double> m = weights_of(model, nu, 1e10, {1e300, 1.0, inf});
      CHECK(m[0] == 0.0);
      CHECK(m[2] == 0.0);
      CHECK(rel_err(m[1], model == WeightModel::kGaussian ? 1.0 : (nu + 3.0) / (nu + 1e10)) <
            1e-14);
      // Every r infinite: equal posteriors, finite weights.
      const std::vector<double> a = weights_of(model, nu, 1.0, {inf, inf, inf}, &lse);
      for (double v : a) CHECK(v == (model == WeightModel::kGaussian ? 1.0 / 3.0 : 0.0));
      CHECK(lse == -inf);
    }
  }
}

// The Student-t kernel takes two neighbours per step in two lanes (e_step_kernel.hpp). Each lane
// must round as the one-neighbour formula written out here: q_k = (nu + z_min) / (nu + r_k / s^2),
// the power by the method the kernel names for that nu, the sum in order, then c and w = c u.
TEST_CASE("Student-t weights equal the one-neighbour formula to the bit, for every count",
          "[weights]") {
  Rng rng(29);
  struct Kernel {
    double nu;
    double (*power)(double q, double d);  // d = (z_min - z) / (nu + z) = q - 1
  };
  // e = (nu + 3) / 2 by the kernel's method: squaring, square roots for eighths, exp(e log1p(d));
  // the products in the kernel's order (PowerDyadic: the roots' product, then the powers of q by
  // squaring, lowest first).
  const Kernel kernels[] = {
      {5.0, [](double q, double) { return (q * q) * (q * q); }},  // e = 4
      {1.25,
       [](double q, double) { return std::sqrt(std::sqrt(std::sqrt(q))) * (q * q); }},  // 2 + 1/8
      {1.5, [](double q, double) { return std::sqrt(std::sqrt(q)) * (q * q); }},        // 2 + 1/4
      {2.0, [](double q, double) { return std::sqrt(q) * (q * q); }},                   // 2 + 1/2
      {1.0, [](double q, double) { return 1.0 * (q * q); }},                            // 2
      {0.25,                                                                            // 1 + 5/8
       [](double q, double) { return (std::sqrt(q) * std::sqrt(std::sqrt(std::sqrt(q)))) * q; }},
      {1.75,  // 2 + 3/8
       [](double q, double) {
         return (std::sqrt(std::sqrt(q)) * std::sqrt(std::sqrt(std::sqrt(q)))) * (q * q);
       }},
      {9.5,  // 6 + 1/4
       [](double q, double) { return (std::sqrt(std::sqrt(q)) * (q * q)) * ((q * q) * (q * q)); }},
      {2.7, [](double q, double d) { return q > 0.0 ? std::exp(2.85 * std::log1p(d)) : 0.0; }},
  };
  int compared = 0;
  for (const Kernel& kernel : kernels) {
    for (std::size_t n = 1; n <= 11; ++n) {
      for (int trial = 0; trial < 20; ++trial) {
        const double inv_s2 = std::pow(10.0, core_test::uniform(rng, -3.0, 3.0));
        std::vector<double> r(n);
        for (double& v : r) v = core_test::uniform(rng, 0.0, 20.0) / inv_s2;
        double r_min = r[0];
        for (double v : r) r_min = v < r_min ? v : r_min;
        const double nu_z_min = kernel.nu + r_min * inv_s2;
        std::vector<double> u(n);
        double sum = 0.0;
        for (std::size_t k = 0; k < n; ++k) {
          const double z = r[k] * inv_s2;
          const double q = nu_z_min / (kernel.nu + z);
          const double p = kernel.power(q, (r_min * inv_s2 - z) / (kernel.nu + z));
          sum += p;
          u[k] = p * q;
        }
        const double c = (kernel.nu + 3.0) / (nu_z_min * sum);
        const double lse =
            -0.5 * (kernel.nu + 3.0) * std::log1p(r_min * inv_s2 / kernel.nu) + std::log(sum);
        double got_lse = 0.0;
        const std::vector<double> w =
            weights_of(WeightModel::kStudentT, kernel.nu, inv_s2, r, &got_lse);
        INFO("nu " << kernel.nu << " n " << n << " trial " << trial);
        for (std::size_t k = 0; k < n; ++k) CHECK(w[k] == u[k] * c);
        CHECK(got_lse == lse);
        ++compared;
      }
    }
  }
  CHECK(compared == 9 * 11 * 20);
}

// The four-lane path (four_lanes.hpp) against the two-lane one, to the bit: u, c and the sum's
// order, for counts around the lanes' widths and every dyadic power of the kernel's range.
TEST_CASE("Student-t: four lanes give the two-lane kernel's weights to the bit", "[weights]") {
  if (!ppcr::detail::four_lanes_available()) {
    WARN("four lanes are not available on this CPU or build: only the two-lane path is tested");
    return;
  }
  Rng rng(31);
  int compared = 0;
  for (int quarters = 1; quarters <= 60; ++quarters) {  // nu = 0.25 ... 15: e = 1.625 ... 9
    const double nu = 0.25 * quarters;
    const double exponent = 0.5 * (nu + 3.0);
    const int whole = static_cast<int>(std::floor(exponent));
    const int eighths = static_cast<int>(8.0 * exponent) - 8 * whole;
    const ppcr::detail::PowerDyadic two{whole, eighths, false}, four{whole, eighths, true};
    for (std::size_t n = 1; n <= 13; ++n) {
      const double inv_s2 = std::pow(10.0, core_test::uniform(rng, -3.0, 3.0));
      std::vector<double> r(n);
      for (double& v : r) v = core_test::uniform(rng, 0.0, 30.0) / inv_s2;
      const double r_min = ppcr::detail::smallest(r.data(), n);
      std::vector<double> u2(n, -1.0), u4(n, -2.0);
      const ppcr::detail::PointWeights a = ppcr::detail::student_t_weights<true>(
          two, nu, exponent, inv_s2, r.data(), r_min, n, u2.data());
      const ppcr::detail::PointWeights b = ppcr::detail::student_t_weights<true>(
          four, nu, exponent, inv_s2, r.data(), r_min, n, u4.data());
      INFO("nu " << nu << " n " << n);
      CHECK(std::memcmp(u2.data(), u4.data(), n * sizeof(double)) == 0);
      CHECK(std::memcmp(&a.c, &b.c, sizeof(double)) == 0);
      CHECK(std::memcmp(&a.log_sum_exp, &b.log_sum_exp, sizeof(double)) == 0);
      ++compared;
    }
  }
  CHECK(compared == 60 * 13);
}

// The Student-t with nu -> infinity is the Gaussian. The ratio q = (nu + z_min) / (nu + z_k)
// rounds to 1 within 1 ulp, and q^e with e = (nu + 3) / 2 multiplied that error by e (at nu =
// 1e100 every weight was wrong); (nu + z_min) * sum overflowed at nu = 1e308 (every weight 0).
TEST_CASE("Student-t at huge dof: the Gaussian's weights and cost, for any finite dof",
          "[weights]") {
  Rng rng(37);
  const double largest = std::numeric_limits<double>::max();
  for (double nu : {1e12, 1e15, 1e100, 1e200, 1e308, largest}) {
    for (int trial = 0; trial < 50; ++trial) {
      const std::size_t n = 1 + trial % 9;
      const double inv_s2 = std::pow(10.0, core_test::uniform(rng, -3.0, 3.0));
      std::vector<double> r(n);
      for (double& v : r) v = core_test::uniform(rng, 0.0, 30.0) / inv_s2;
      double lse_t = 0.0, lse_g = 0.0;
      const std::vector<double> t = weights_of(WeightModel::kStudentT, nu, inv_s2, r, &lse_t);
      const std::vector<double> g = weights_of(WeightModel::kGaussian, nu, inv_s2, r, &lse_g);
      INFO("nu " << nu << " n " << n << " trial " << trial);
      // The weights differ from the Gaussian's by O(z / nu): 1e-9 covers z <= 30 at nu = 1e12.
      for (std::size_t k = 0; k < n; ++k) CHECK(std::abs(t[k] - g[k]) <= 1e-9 * (1.0 + g[k]));
      CHECK(std::abs(lse_t - lse_g) <= 1e-9 * (1.0 + std::abs(lse_g)));
    }
  }
}
