// Tests of detail::ScaleSchedule (the E-step scale across outer iterations) on scripted updates,
// against the schedule documented in ppcr/weights.hpp, values worked out by hand.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "model/e_step.hpp"
#include "registration/scale_schedule.hpp"

using ppcr::ScaleMode;
using ppcr::WeightOptions;
using ppcr::detail::ScaleSchedule;

namespace {

WeightOptions em(double scale = 0.0) {
  WeightOptions o;
  o.scale_mode = ScaleMode::kEM;
  o.scale = scale;
  return o;
}

}  // namespace

TEST_CASE("raw and fixed scales never change and never settle", "[scale_schedule]") {
  WeightOptions raw;
  raw.scale_mode = ScaleMode::kRaw;
  raw.scale = 7.0;  // unused by kRaw
  ScaleSchedule r(raw, 0.4);
  CHECK(r.scale_sq() == 1.0);
  CHECK_FALSE(r.settling());
  WeightOptions fixed;
  fixed.scale_mode = ScaleMode::kFixed;
  fixed.scale = 0.25;
  ScaleSchedule f(fixed, 0.4);
  CHECK(f.scale_sq() == 0.0625);
  CHECK_FALSE(f.settling());
  for (int i = 0; i < 20; ++i) {
    r.update(0.0, 0.0, 1e-6);
    f.update(0.0, 0.0, 1e-6);
  }
  CHECK(r.scale_sq() == 1.0);
  CHECK(f.scale_sq() == 0.0625);
  CHECK_FALSE(r.settling());
  CHECK_FALSE(f.settling());
}

TEST_CASE("EM: the coarse scale is the given one, or radius / 2", "[scale_schedule]") {
  ScaleSchedule a(em(0.0), 0.5);
  CHECK(a.scale_sq() == 0.0625);  // (0.5 / 2)^2
  CHECK(a.settling());
  ScaleSchedule b(em(0.75), 0.5);
  CHECK(b.scale_sq() == 0.5625);
  CHECK(b.settling());
}

TEST_CASE("EM coarse phase: held until more than patience low drops", "[scale_schedule]") {
  WeightOptions o = em(0.0);     // s = 0.5 for radius 1
  o.em_coarse_max_motion = 0.0;  // motion-blind count (the guard has its own test below)
  o.em_coarse_drop = 0.01;
  o.em_coarse_patience = 3;
  o.em_coarse_motion = 1e-3;
  o.em_min_shrink = 0.5;
  ScaleSchedule s(o, 1.0);
  // Large motion (no "still" exit), low drops: held for 3, settles at the 4th.
  for (int i = 0; i < 3; ++i) {
    s.update(0.001, 0.1, 1e-4);
    CHECK(s.scale_sq() == 0.25);
    CHECK(s.settling());
  }
  // A drop at the threshold is not low: resets the count.
  s.update(0.01, 0.1, 1e-4);
  CHECK(s.scale_sq() == 0.25);
  for (int i = 0; i < 3; ++i) s.update(0.001, 0.1, 1e-4);
  CHECK(s.scale_sq() == 0.25);
  CHECK(s.settling());
  // 4th consecutive low drop: refine starts with this iteration's estimate, limited to a
  // shrink of em_min_shrink (0.5): max(1e-4, 0.125) = 0.125, still settling (at the limit).
  s.update(0.001, 0.1, 1e-4);
  CHECK(s.scale_sq() == 0.125);
  CHECK(s.settling());
}

TEST_CASE("EM coarse phase: one iteration that barely moves the source settles it",
          "[scale_schedule]") {
  WeightOptions o = em(0.2);  // s = 0.2, threshold motion 0.2 * 1e-3 = 2e-4
  ScaleSchedule s(o, 1.0);
  s.update(0.5, 3e-4, 0.01);  // moved 3e-4 > 2e-4: held
  CHECK(s.scale_sq() == Approx(0.04).epsilon(1e-15));
  s.update(0.5, 1.5e-4, 0.03);  // moved 1.5e-4 < 2e-4: settled, EM estimate 0.03 > 0.5 * 0.04
  CHECK(s.scale_sq() == 0.03);
  CHECK_FALSE(s.settling());
}

TEST_CASE("EM refine phase: shrink limit, growth and floor", "[scale_schedule]") {
  WeightOptions o = em(1.0);
  o.em_coarse_max_motion = 0.0;  // motion-blind count (the guard has its own test below)
  o.em_coarse_patience = 0;
  o.em_min_shrink = 0.25;
  o.em_min_scale = 0.1;  // floor s^2 = 0.01
  ScaleSchedule s(o, 1.0);
  s.update(0.0, 1.0, 0.5);  // settles at once (1 low drop > patience 0): 0.5 > 0.25
  CHECK(s.scale_sq() == 0.5);
  CHECK_FALSE(s.settling());
  s.update(0.0, 1.0, 1e-6);  // limited to 0.25 * 0.5 = 0.125: settling
  CHECK(s.scale_sq() == 0.125);
  CHECK(s.settling());
  s.update(0.0, 1.0, 2.0);  // the estimate may grow
  CHECK(s.scale_sq() == 2.0);
  CHECK_FALSE(s.settling());
  // Shrinking at the limit down to the floor: 0.5, 0.125, 0.03125, then floored at 0.01.
  s.update(0.0, 1.0, 1e-9);
  CHECK(s.scale_sq() == 0.5);
  s.update(0.0, 1.0, 1e-9);
  CHECK(s.scale_sq() == 0.125);
  s.update(0.0, 1.0, 1e-9);
  CHECK(s.scale_sq() == 0.03125);
  CHECK(s.settling());
  s.update(0.0, 1.0, 1e-9);
  CHECK(s.scale_sq() == 0.1 * 0.1);  // em_min_scale^2
  // At the floor the scale no longer shrinks: not settling.
  CHECK_FALSE(s.settling());
  s.update(0.0, 1.0, 1e-9);
  CHECK(s.scale_sq() == 0.1 * 0.1);  // em_min_scale^2
  CHECK_FALSE(s.settling());
}

TEST_CASE("EM: a NaN cost drop counts as settled, a non-finite estimate keeps the scale",
          "[scale_schedule]") {
  WeightOptions o = em(0.5);  // s^2 = 0.25
  o.em_coarse_patience = 0;
  // Radius 1: a motion below em_coarse_max_motion x 1 = 0.02 is slow, one below
  // em_coarse_motion x 0.5 = 5e-4 is still. 0.01 is slow and not still, so only the drop decides.
  REQUIRE(o.em_coarse_max_motion == 0.02);
  REQUIRE(o.em_coarse_motion == 1e-3);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ScaleSchedule moving(o, 1.0);
  moving.update(nan, 1.0, 0.2);  // a moving source: its drop, NaN or not, is not counted
  CHECK(moving.coarse());
  CHECK(moving.scale_sq() == 0.25);
  ScaleSchedule s(o, 1.0);
  s.update(nan, 0.01, 0.2);  // slow: the NaN drop counts as low, 1 > patience 0: settled
  CHECK_FALSE(s.coarse());
  CHECK(s.scale_sq() == 0.2);
  s.update(0.5, 1.0, std::numeric_limits<double>::infinity());
  CHECK(s.scale_sq() == 0.2);
  CHECK(std::isfinite(s.scale_sq()));
}

TEST_CASE("EM coarse phase with em_coarse_max_motion: moving iterations do not count",
          "[scale_schedule]") {
  WeightOptions o = em(0.5);  // s^2 = 0.25
  o.em_coarse_patience = 1;
  o.em_coarse_motion = 1e-6;      // no "still" exit in this script
  o.em_coarse_max_motion = 0.25;  // of the radius 2: motions below 0.5 count
  o.em_min_shrink = 0.5;
  ScaleSchedule s(o, 2.0);
  s.update(0.0, 0.75, 0.01);  // low drop but moving: not counted
  s.update(0.0, 0.5, 0.01);   // exactly the limit: not counted
  s.update(0.0, 0.25, 0.01);  // counted: 1
  CHECK(s.scale_sq() == 0.25);
  s.update(0.0, 0.75, 0.01);  // moving: reset
  s.update(0.0, 0.25, 0.01);  // 1
  CHECK(s.scale_sq() == 0.25);
  CHECK(s.settling());
  s.update(0.0, 0.25, 0.01);  // 2 > patience: settles; max(0.01, 0.125) = 0.125
  CHECK(s.scale_sq() == 0.125);
}
