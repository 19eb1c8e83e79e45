// Tests of TerminationMonitor on scripted IterationReport sequences: for each criterion the exact
// iteration it fires at, as documented in ppcr/termination.hpp, derived by hand for each script.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "core_test_util.hpp"
#include "ppcr/metrics.hpp"
#include "registration/termination.hpp"

using ppcr::IterationReport;
using ppcr::StopReason;
using ppcr::TerminationCriteria;
using ppcr::TerminationMonitor;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

ppcr::CloudMoments some_moments() {
  core_test::Rng rng(71);
  return ppcr::compute_moments(core_test::uniform_cloud(rng, 100, -1.0, 1.0));
}

IterationReport report(int t, double initial, double final_cost, int steps = 5,
                       const Eigen::Isometry3d& T = Eigen::Isometry3d::Identity(),
                       bool settling = false) {
  IterationReport r;
  r.iteration = t;
  r.lm.initial_cost = initial;
  r.lm.final_cost = final_cost;
  r.lm.successful_steps = steps;
  r.lm.iterations = steps;
  r.T_target_source = T;
  r.scale_settling = settling;
  return r;
}

Eigen::Isometry3d shift(double x) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return T;
}

TerminationCriteria only(std::uint32_t criteria) {
  TerminationCriteria c;
  c.criteria = criteria;
  c.max_iterations = 1000;
  return c;
}

// Feeds reports made by make(t) for t = 1, 2, ... until the monitor stops or t reaches limit.
// Returns the iteration it stopped at (0 if it never did) and the reason.
template <class F>
std::pair<int, StopReason> run(TerminationMonitor& m, F make, int limit = 200) {
  for (int t = 1; t <= limit; ++t) {
    const StopReason r = m.update(make(t));
    if (r != StopReason::kNone) return {t, r};
  }
  return {0, StopReason::kNone};
}

}  // namespace

TEST_CASE("cost drop fires at the (patience+1)-th consecutive low iteration", "[termination]") {
  for (int patience : {0, 1, 10, 20}) {
    TerminationCriteria c = only(ppcr::kCriterionCostDrop);
    c.cost_drop_patience = patience;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    // drop = 0.001 < 0.01 at every iteration.
    const auto stop = run(m, [](int t) { return report(t, 1.0, 0.999); });
    INFO("patience " << patience);
    CHECK(stop.first == patience + 1);
    CHECK(stop.second == StopReason::kCostDrop);
  }
}

TEST_CASE("cost drop: one iteration at or above the threshold resets the counter",
          "[termination]") {
  for (int patience : {1, 3, 10}) {
    TerminationCriteria c = only(ppcr::kCriterionCostDrop);
    c.cost_drop_threshold = 0.25;  // 0.25 = (1 - 0.75) / 1 exactly in binary
    c.cost_drop_patience = patience;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    // patience lows, then one drop exactly at the threshold (not low), then lows again.
    const int reset_at = patience + 1;
    const auto stop =
        run(m, [&](int t) { return t == reset_at ? report(t, 1.0, 0.75) : report(t, 1.0, 0.9); });
    INFO("patience " << patience);
    CHECK(stop.first == reset_at + patience + 1);
    CHECK(stop.second == StopReason::kCostDrop);
  }
}

TEST_CASE("cost drop: a drop exactly equal to the threshold is not low", "[termination]") {
  TerminationCriteria c = only(ppcr::kCriterionCostDrop);
  c.cost_drop_threshold = 0.25;
  c.cost_drop_patience = 0;
  TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
  const auto stop = run(
      m, [](int t) { return report(t, 4.0, 3.0); }, 100);
  CHECK(stop.first == 0);
  CHECK(m.last_cost_drop() == 0.25);
  // The next double below the threshold is low.
  TerminationMonitor m2(c, some_moments(), Eigen::Isometry3d::Identity());
  CHECK(m2.update(report(1, 4.0, std::nextafter(3.0, 4.0))) == StopReason::kCostDrop);
}

TEST_CASE("cost drop: first-iteration behaviour", "[termination]") {
  TerminationCriteria c = only(ppcr::kCriterionCostDrop);
  c.cost_drop_patience = 0;
  {
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(m.update(report(1, 2.0, 1.99)) == StopReason::kCostDrop);
    CHECK(m.last_cost_drop() == Approx(0.005).epsilon(1e-12));
  }
  {
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(m.update(report(1, 2.0, 1.0)) == StopReason::kNone);
    CHECK(m.last_cost_drop() == 0.5);
    CHECK(m.update(report(2, 2.0, 1.99)) == StopReason::kCostDrop);
  }
  // The default patience, the option's (4): not before iteration 5 even when every drop is low.
  const int patience = ppcr::ExpertOptions{}.cost_drop_patience;
  CHECK(TerminationCriteria{}.cost_drop_patience == patience);
  TerminationMonitor m(only(ppcr::kCriterionCostDrop), some_moments(),
                       Eigen::Isometry3d::Identity());
  CHECK(run(m, [](int t) { return report(t, 1.0, 1.0); }).first == patience + 1);
}

TEST_CASE("cost drop: negative drops (cost went up) are low", "[termination]") {
  TerminationCriteria c = only(ppcr::kCriterionCostDrop);
  c.cost_drop_patience = 3;
  TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
  const auto stop = run(m, [](int t) { return report(t, 1.0, 1.5); });
  CHECK(stop.first == 4);
  CHECK(stop.second == StopReason::kCostDrop);
  CHECK(m.last_cost_drop() == -0.5);
}

TEST_CASE("zero initial cost gives kZeroCost, NaN or Inf costs give kNumericalFailure",
          "[termination]") {
  for (std::uint32_t criteria : {0u, static_cast<std::uint32_t>(ppcr::kCriterionCostDrop),
                                 static_cast<std::uint32_t>(ppcr::kCriterionFixed | 0xEu)}) {
    TerminationCriteria c = only(criteria);
    c.fixed_iterations = 1;
    {
      TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
      CHECK(m.update(report(1, 0.0, 0.0)) == StopReason::kZeroCost);
      CHECK(std::isnan(m.last_cost_drop()));
    }
    for (double initial : {kNaN, kInf, -kInf, 1.0}) {
      for (double final_cost : {kNaN, kInf, 0.5}) {
        if (std::isfinite(initial) && std::isfinite(final_cost)) continue;
        TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
        INFO("criteria " << criteria << " initial " << initial << " final " << final_cost);
        CHECK(m.update(report(1, initial, final_cost)) == StopReason::kNumericalFailure);
        CHECK(std::isnan(m.last_cost_drop()));
      }
    }
    // Zero initial cost with a non-finite final cost: the non-finite check comes first.
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(m.update(report(1, 0.0, kNaN)) == StopReason::kNumericalFailure);
  }
}

TEST_CASE("a NaN report never reaches the cost-drop counter", "[termination]") {
  TerminationCriteria c = only(ppcr::kCriterionCostDrop);
  c.cost_drop_patience = 2;
  TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
  CHECK(m.update(report(1, 1.0, 0.999)) == StopReason::kNone);  // low 1
  CHECK(m.update(report(2, 1.0, 0.999)) == StopReason::kNone);  // low 2
  CHECK(m.update(report(3, kNaN, 0.5)) == StopReason::kNumericalFailure);
  CHECK(m.update(report(4, 0.0, 0.0)) == StopReason::kZeroCost);
  // Neither the NaN nor the zero cost counted or reset: the third low fires.
  CHECK(m.update(report(5, 1.0, 0.999)) == StopReason::kCostDrop);
}

TEST_CASE("fixed iterations fires at N", "[termination]") {
  for (int n : {1, 2, 7, 100}) {
    TerminationCriteria c = only(ppcr::kCriterionFixed);
    c.fixed_iterations = n;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    const auto stop = run(m, [](int t) { return report(t, 1.0, 0.999); });
    CHECK(stop.first == n);
    CHECK(stop.second == StopReason::kFixedIterations);
  }
}

TEST_CASE("the hard cap fires at max_iterations when no criterion did", "[termination]") {
  for (std::uint32_t criteria :
       {0u, static_cast<std::uint32_t>(ppcr::kCriterionCostDrop),
        static_cast<std::uint32_t>(ppcr::kCriterionFixed | ppcr::kCriterionCostDrop |
                                   ppcr::kCriterionMsePrev | ppcr::kCriterionSuccessfulSteps)}) {
    TerminationCriteria c = only(criteria);
    c.max_iterations = 6;
    c.fixed_iterations = 50;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    // High drops, many steps, a pose moving by the same amount every time: nothing fires.
    const auto stop = run(m, [](int t) { return report(t, 1.0, 0.5, 10, shift(0.1 * t)); });
    INFO("criteria " << criteria);
    CHECK(stop.first == 6);
    CHECK(stop.second == StopReason::kMaxIterations);
  }
  // max_iterations = 1: stops after the first iteration.
  TerminationCriteria c = only(ppcr::kCriterionCostDrop);
  c.max_iterations = 1;
  TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
  CHECK(m.update(report(1, 1.0, 0.5)) == StopReason::kMaxIterations);
}

TEST_CASE("several criteria: the first in the documented order wins", "[termination]") {
  // Order: fixed, cost drop, MSE, successful steps, then the cap.
  SECTION("fixed and cap at the same iteration: fixed") {
    TerminationCriteria c = only(ppcr::kCriterionFixed);
    c.fixed_iterations = 4;
    c.max_iterations = 4;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m, [](int t) { return report(t, 1.0, 0.5); }) ==
          std::make_pair(4, StopReason::kFixedIterations));
  }
  SECTION("fixed beyond the cap: the cap") {
    TerminationCriteria c = only(ppcr::kCriterionFixed);
    c.fixed_iterations = 10;
    c.max_iterations = 4;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m, [](int t) { return report(t, 1.0, 0.5); }) ==
          std::make_pair(4, StopReason::kMaxIterations));
  }
  SECTION("cost drop and cap at the same iteration: cost drop") {
    TerminationCriteria c = only(ppcr::kCriterionCostDrop);
    c.cost_drop_patience = 3;
    c.max_iterations = 4;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m, [](int t) { return report(t, 1.0, 1.0); }) ==
          std::make_pair(4, StopReason::kCostDrop));
  }
  SECTION("fixed and cost drop at the same iteration: fixed") {
    TerminationCriteria c = only(ppcr::kCriterionFixed | ppcr::kCriterionCostDrop);
    c.fixed_iterations = 3;
    c.cost_drop_patience = 2;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m, [](int t) { return report(t, 1.0, 1.0); }) ==
          std::make_pair(3, StopReason::kFixedIterations));
  }
  SECTION("cost drop, MSE and successful steps at the same iteration: cost drop") {
    TerminationCriteria c =
        only(ppcr::kCriterionCostDrop | ppcr::kCriterionMsePrev | ppcr::kCriterionSuccessfulSteps);
    c.cost_drop_patience = 2;
    c.mse_patience = 2;
    c.successful_steps_patience = 2;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    // Pose never moves (MSE 0: low from t = 1), 0 steps, zero drop: all fire at t = 3.
    CHECK(run(m, [](int t) { return report(t, 1.0, 1.0, 0); }) ==
          std::make_pair(3, StopReason::kCostDrop));
  }
  SECTION("MSE and successful steps at the same iteration: MSE") {
    TerminationCriteria c = only(ppcr::kCriterionMsePrev | ppcr::kCriterionSuccessfulSteps);
    c.mse_patience = 2;
    c.successful_steps_patience = 2;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m, [](int t) { return report(t, 1.0, 0.5, 0); }) ==
          std::make_pair(3, StopReason::kMsePrev));
  }
  SECTION("the earliest criterion stops the loop whatever the order") {
    TerminationCriteria c = only(ppcr::kCriterionFixed | ppcr::kCriterionSuccessfulSteps);
    c.fixed_iterations = 9;
    c.successful_steps_patience = 1;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m, [](int t) { return report(t, 1.0, 0.5, 1); }) ==
          std::make_pair(2, StopReason::kSuccessfulSteps));
  }
}

TEST_CASE("MSE w.r.t. the previous pose: ratio and patience on scripted poses", "[termination]") {
  // Pure translations along x: MSE_t = (x_t - x_{t-1})^2 exactly, whatever the cloud.
  SECTION("motion halving every iteration: MSE ratio 4 > 2, low from t = 2") {
    for (int patience : {0, 1, 3, 5}) {
      TerminationCriteria c = only(ppcr::kCriterionMsePrev);
      c.mse_patience = patience;
      TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
      // x_t = 1 - 2^-t: steps 2^-t.
      const auto stop =
          run(m, [](int t) { return report(t, 1.0, 0.5, 5, shift(1.0 - std::ldexp(1.0, -t))); });
      INFO("patience " << patience);
      CHECK(stop.first == patience + 2);
      CHECK(stop.second == StopReason::kMsePrev);
      CHECK(m.last_mse_prev() == std::ldexp(1.0, -2 * stop.first));
    }
  }
  SECTION("an MSE exactly MSE_prev / ratio is not low; slightly below is") {
    TerminationCriteria c = only(ppcr::kCriterionMsePrev);
    c.mse_patience = 0;
    c.mse_ratio_threshold = 4.0;  // steps halving: MSE exactly a quarter
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(
              m, [](int t) { return report(t, 1.0, 0.5, 5, shift(1.0 - std::ldexp(1.0, -t))); }, 30)
              .first == 0);
    c.mse_ratio_threshold = 3.99;
    TerminationMonitor m2(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m2, [](int t) {
            return report(t, 1.0, 0.5, 5, shift(1.0 - std::ldexp(1.0, -t)));
          }).first == 2);
  }
  SECTION("constant motion is never low") {
    TerminationCriteria c = only(ppcr::kCriterionMsePrev);
    c.mse_patience = 0;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(
              m, [](int t) { return report(t, 1.0, 0.5, 5, shift(0.5 * t)); }, 50)
              .first == 0);
    CHECK(m.last_mse_prev() == 0.25);
  }
  SECTION("a pose that never moves: MSE 0 is low from t = 1") {
    for (int patience : {0, 3}) {
      TerminationCriteria c = only(ppcr::kCriterionMsePrev);
      c.mse_patience = patience;
      TerminationMonitor m(c, some_moments(), shift(2.0));
      const auto stop = run(m, [](int t) { return report(t, 1.0, 0.5, 5, shift(2.0)); });
      CHECK(stop.first == patience + 1);
      CHECK(m.last_mse_prev() == 0.0);
    }
  }
  SECTION("a larger motion resets the counter") {
    TerminationCriteria c = only(ppcr::kCriterionMsePrev);
    c.mse_patience = 2;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    // Steps: 1, 1/4, 1/16 (low, low), 1 (not low), 1/4, 1/16, 1/64 (low x3: fires at t = 7).
    const double steps[] = {1.0, 0.25, 0.0625, 1.0, 0.25, 0.0625, 0.015625, 0.00390625};
    double x = 0.0;
    const auto stop = run(
        m,
        [&](int t) {
          x += steps[t - 1];
          return report(t, 1.0, 0.5, 5, shift(x));
        },
        8);
    CHECK(stop == std::make_pair(7, StopReason::kMsePrev));
  }
  SECTION("T_0 is the initial pose given to the monitor") {
    TerminationMonitor m(only(ppcr::kCriterionMsePrev), some_moments(), shift(-3.0));
    m.update(report(1, 1.0, 0.5, 5, shift(1.0)));
    CHECK(m.last_mse_prev() == 16.0);
  }
}

TEST_CASE("last_mse_prev equals the brute-force mean over the source for rotations",
          "[termination]") {
  core_test::Rng rng(72);
  const ppcr::PointCloud cloud = core_test::uniform_cloud(rng, 2000, -2.0, 3.0);
  const Eigen::Isometry3d T0 =
      core_test::make_pose(Eigen::Vector3d(1, 0, 0), 0.2, Eigen::Vector3d(1, 2, 3));
  TerminationMonitor m(only(ppcr::kCriterionMsePrev), ppcr::compute_moments(cloud), T0);
  Eigen::Isometry3d prev = T0;
  for (int t = 1; t <= 5; ++t) {
    const Eigen::Isometry3d T = core_test::make_pose(core_test::random_unit_vector(rng), 0.3 * t,
                                                     core_test::random_unit_vector(rng));
    m.update(report(t, 1.0, 0.5, 5, T));
    double sum = 0.0;
    for (const Eigen::Vector3d& x : cloud) sum += (T * x - prev * x).squaredNorm();
    CHECK(m.last_mse_prev() == Approx(sum / static_cast<double>(cloud.size())).epsilon(1e-10));
    prev = T;
  }
}

TEST_CASE("successful-steps criterion", "[termination]") {
  TerminationCriteria c = only(ppcr::kCriterionSuccessfulSteps);
  c.successful_steps_threshold = 1;
  c.successful_steps_patience = 3;
  {
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    // Low when steps <= 1: 0, 1, 1 then 2 resets; 1, 0, 1, 1 fires at the 4th low (t = 8).
    const int steps[] = {0, 1, 1, 2, 1, 0, 1, 1, 1};
    const auto stop = run(
        m, [&](int t) { return report(t, 1.0, 0.5, steps[t - 1]); }, 9);
    CHECK(stop == std::make_pair(8, StopReason::kSuccessfulSteps));
  }
  {
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(
              m, [](int t) { return report(t, 1.0, 0.5, 2); }, 50)
              .first == 0);
  }
}

TEST_CASE("scale_settling holds the adaptive counters at zero", "[termination]") {
  SECTION("cost drop") {
    TerminationCriteria c = only(ppcr::kCriterionCostDrop);
    c.cost_drop_patience = 2;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    // Low drops throughout; settling for t = 1..5: counting starts at t = 6, fires at t = 8.
    const auto stop = run(
        m, [](int t) { return report(t, 1.0, 0.999, 5, Eigen::Isometry3d::Identity(), t <= 5); });
    CHECK(stop == std::make_pair(8, StopReason::kCostDrop));
  }
  SECTION("settling in the middle resets the counter") {
    TerminationCriteria c = only(ppcr::kCriterionCostDrop);
    c.cost_drop_patience = 2;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    const auto stop = run(
        m, [](int t) { return report(t, 1.0, 0.999, 5, Eigen::Isometry3d::Identity(), t == 3); });
    CHECK(stop == std::make_pair(6, StopReason::kCostDrop));
  }
  SECTION("MSE and successful steps") {
    TerminationCriteria c = only(ppcr::kCriterionMsePrev | ppcr::kCriterionSuccessfulSteps);
    c.mse_patience = 1;
    c.successful_steps_patience = 1;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    const auto stop =
        run(m, [](int t) { return report(t, 1.0, 0.5, 0, Eigen::Isometry3d::Identity(), t <= 4); });
    CHECK(stop == std::make_pair(6, StopReason::kMsePrev));
  }
  SECTION("fixed iterations and the cap still apply") {
    TerminationCriteria c = only(ppcr::kCriterionFixed | ppcr::kCriterionCostDrop);
    c.fixed_iterations = 3;
    c.cost_drop_patience = 0;
    TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m, [](int t) {
            return report(t, 1.0, 0.999, 5, Eigen::Isometry3d::Identity(), true);
          }) == std::make_pair(3, StopReason::kFixedIterations));
    TerminationCriteria cap = only(ppcr::kCriterionCostDrop);
    cap.max_iterations = 5;
    cap.cost_drop_patience = 0;
    TerminationMonitor m2(cap, some_moments(), Eigen::Isometry3d::Identity());
    CHECK(run(m2, [](int t) {
            return report(t, 1.0, 0.999, 5, Eigen::Isometry3d::Identity(), true);
          }) == std::make_pair(5, StopReason::kMaxIterations));
  }
}

TEST_CASE("last_cost_drop is (initial - final) / initial", "[termination]") {
  TerminationMonitor m(only(0u), some_moments(), Eigen::Isometry3d::Identity());
  m.update(report(1, 8.0, 6.0));
  CHECK(m.last_cost_drop() == 0.25);
  m.update(report(2, 3.0, 2.0));
  CHECK(m.last_cost_drop() == Approx(1.0 / 3.0).epsilon(1e-15));
  m.update(report(3, 2.0, 0.0));
  CHECK(m.last_cost_drop() == 1.0);
}

TEST_CASE("is_criterion_stop: true for the four criteria", "[termination]") {
  CHECK(ppcr::is_criterion_stop(StopReason::kFixedIterations));
  CHECK(ppcr::is_criterion_stop(StopReason::kCostDrop));
  CHECK(ppcr::is_criterion_stop(StopReason::kMsePrev));
  CHECK(ppcr::is_criterion_stop(StopReason::kSuccessfulSteps));
  CHECK_FALSE(ppcr::is_criterion_stop(StopReason::kNone));
  CHECK_FALSE(ppcr::is_criterion_stop(StopReason::kMaxIterations));
  CHECK_FALSE(ppcr::is_criterion_stop(StopReason::kNoCorrespondences));
  CHECK_FALSE(ppcr::is_criterion_stop(StopReason::kNumericalFailure));
  CHECK_FALSE(ppcr::is_criterion_stop(StopReason::kInvalidInput));
  CHECK_FALSE(ppcr::is_criterion_stop(StopReason::kCancelled));
}

TEST_CASE("cost drop with cost_drop_max_motion: a low drop counts only if the source was still",
          "[termination]") {
  TerminationCriteria c = only(ppcr::kCriterionCostDrop);
  c.cost_drop_patience = 1;
  c.cost_drop_max_motion = 0.25;  // fraction of motion_reference (RMS motion, sqrt of MSE_t)
  TerminationMonitor m(c, some_moments(), Eigen::Isometry3d::Identity());
  // Pure translations: RMS motion = step. Steps: 0.5 (moving: not low), 0.125 (low), 0.25
  // (exactly the limit: not low), 0.125, 0.125 (low x2: fires at t = 5). motion_reference 1.
  const double steps[] = {0.5, 0.125, 0.25, 0.125, 0.125, 0.125};
  double x = 0.0;
  const auto stop = run(
      m,
      [&](int t) {
        x += steps[t - 1];
        IterationReport r = report(t, 1.0, 0.999, 5, shift(x));
        r.motion_reference = 1.0;
        return r;
      },
      6);
  CHECK(stop == std::make_pair(5, StopReason::kCostDrop));
  // The limit scales with motion_reference: with reference 4 every step above is still.
  TerminationMonitor m2(c, some_moments(), Eigen::Isometry3d::Identity());
  x = 0.0;
  const auto stop2 = run(
      m2,
      [&](int t) {
        x += steps[t - 1];
        IterationReport r = report(t, 1.0, 0.999, 5, shift(x));
        r.motion_reference = 4.0;
        return r;
      },
      6);
  CHECK(stop2 == std::make_pair(2, StopReason::kCostDrop));
}
