// Resource bounds of a registration (issue #7): whatever the input, a run is bounded by its
// iteration caps (outer max_iterations, LM max_iterations per outer iteration), every outer
// iteration is seen once by on_iteration, and on_iteration can cancel at any iteration.
// (The bounds of the file readers - headers claiming more points than the file holds - are
// tested in tests/io/test_hostile_inputs.cpp.)
#include <catch2/catch.hpp>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "ppcr/registration.hpp"
#include "reliability_util.hpp"

using ppcr::ErrorModel;
using ppcr::PointCloud;
using ppcr::RegistrationOptions;
using ppcr::RegistrationResult;
using ppcr::StopReason;
using rel_test::describe;
using rel_test::Rng;

namespace {

const ErrorModel kModels[] = {ErrorModel::kPoint, ErrorModel::kPlane};

struct Problem {
  const char* what;
  PointCloud source, target;
  RegistrationOptions options;
};

// Inputs that never satisfy an adaptive criterion on their own, or take long to: uniform noise
// against uniform noise, a line (a free direction), a huge radius (the EM scale overflows and
// never settles), identical points with a far source outlier (the EM scale keeps shrinking).
std::vector<Problem> adversarial_problems(ErrorModel model) {
  Rng rng(21);
  std::vector<Problem> out;
  RegistrationOptions o;
  o.radius = 0.3;
  o.error_model = model;
  PointCloud noise_a, noise_b;
  for (int i = 0; i < 800; ++i) {
    noise_a.emplace_back(rel_test::uniform(rng, -1, 1), rel_test::uniform(rng, -1, 1),
                         rel_test::uniform(rng, -1, 1));
    noise_b.emplace_back(rel_test::uniform(rng, -1, 1), rel_test::uniform(rng, -1, 1),
                         rel_test::uniform(rng, -1, 1));
  }
  out.push_back({"noise against noise", noise_a, noise_b, o});
  const PointCloud line = rel_test::line_cloud(rng, 300);
  out.push_back(
      {"a line", rel_test::transformed(line, rel_test::small_motion().inverse()), line, o});
  const PointCloud scene = rel_test::box_scene(rng, 800);
  Problem huge{"radius 1e300", rel_test::transformed(scene, rel_test::small_motion().inverse()),
               scene, o};
  huge.options.radius = 1e300;
  out.push_back(huge);
  PointCloud with_outlier = scene;
  with_outlier.emplace_back(1e6, 0, 0);
  out.push_back({"same points plus a source point at 1e6 m", with_outlier, scene, o});
  return out;
}

}  // namespace

TEST_CASE("the outer cap bounds every run, whatever the input", "[reliability][bounds]") {
  for (ErrorModel model : kModels) {
    for (Problem& p : adversarial_problems(model)) {
      for (int cap : {1, 3, 8}) {
        INFO(p.what << ", model " << static_cast<int>(model) << ", max_iterations " << cap);
        RegistrationOptions o = p.options;
        o.max_iterations = cap;
        int calls = 0;
        o.on_iteration = [&](const ppcr::IterationRecord& rec) {
          ++calls;
          CHECK(rec.iteration == calls);
          return true;
        };
        const RegistrationResult r = ppcr::align(p.source, p.target, o);
        INFO(describe(r));
        CHECK(rel_test::invariant_violation(r, o) == "");
        CHECK(r.iterations <= cap);
        CHECK(calls == r.iterations);
        CHECK(static_cast<int>(r.history.size()) == r.iterations);
        // Without any criterion only the cap (or a failure) can stop the loop.
        o.criteria = 0;
        calls = 0;
        const RegistrationResult c = ppcr::align(p.source, p.target, o);
        INFO("no criterion: " << describe(c));
        CHECK(rel_test::invariant_violation(c, o) == "");
        if (c.status.ok() && c.stop_reason != StopReason::kZeroCost) {
          CHECK(c.stop_reason == StopReason::kMaxIterations);
          CHECK(c.iterations == cap);
        }
        CHECK(calls == c.iterations);
      }
    }
  }
}

TEST_CASE("lm.max_iterations bounds each inner problem, and is reached", "[reliability][bounds]") {
  Rng rng(22);
  const PointCloud target = rel_test::box_scene(rng, 1500);
  // A large initial misalignment: the first inner problems want many LM steps.
  const Eigen::Isometry3d M =
      rel_test::make_pose(Eigen::Vector3d(1, 1, 0), 0.15, Eigen::Vector3d(0.1, -0.08, 0.05));
  const PointCloud source = rel_test::transformed(target, M.inverse());
  for (ErrorModel model : kModels) {
    for (int lm_cap : {1, 2, 5}) {
      INFO("model " << static_cast<int>(model) << ", lm.max_iterations " << lm_cap);
      RegistrationOptions o;
      o.radius = 0.3;
      o.error_model = model;
      o.expert.lm_max_iterations = lm_cap;
      o.expert.lm_function_tolerance =
          0.0;  // only the cap (or a rejected run of steps) stops the LM
      o.expert.lm_fine_function_tolerance = 0.0;  // in the EM fine phase too (its default is 1e-2)
      o.max_iterations = 20;
      const RegistrationResult r = ppcr::align(source, target, o);
      INFO(describe(r));
      CHECK(rel_test::invariant_violation(r, o) == "");
      REQUIRE(r.status.ok());
      int total = 0, at_cap = 0;
      for (const ppcr::IterationRecord& h : r.history) {
        const int steps = h.successful_steps + h.unsuccessful_steps;
        CHECK(steps <= lm_cap);
        total += steps;
        at_cap += steps == lm_cap;
      }
      CHECK(total == r.lm_iterations);
      CHECK(r.lm_iterations <= r.iterations * lm_cap);
      CHECK(at_cap > 0);  // the cap was the binding limit at least once: not a vacuous bound
    }
  }
}

TEST_CASE("on_iteration cancels at any iteration, a criterion firing then takes precedence",
          "[reliability][bounds]") {
  Rng rng(23);
  const PointCloud target = rel_test::box_scene(rng, 1000);
  const PointCloud source = rel_test::transformed(target, rel_test::small_motion().inverse());
  for (ErrorModel model : kModels) {
    RegistrationOptions o;
    o.radius = 0.2;
    o.error_model = model;
    const RegistrationResult full = ppcr::align(source, target, o);
    REQUIRE(full.status.ok());
    REQUIRE(full.iterations > 6);
    for (int stop_at = 1; stop_at <= 6; ++stop_at) {
      INFO("model " << static_cast<int>(model) << ", cancel at " << stop_at);
      RegistrationOptions c = o;
      int calls = 0;
      c.on_iteration = [&](const ppcr::IterationRecord& rec) {
        ++calls;
        return rec.iteration < stop_at;
      };
      const RegistrationResult r = ppcr::align(source, target, c);
      CHECK(rel_test::invariant_violation(r, c) == "");
      CHECK(r.status.ok());
      CHECK(r.stop_reason == StopReason::kCancelled);
      CHECK_FALSE(r.converged());
      CHECK(r.iterations == stop_at);
      CHECK(calls == stop_at);
      // The cancelled run is the full run's prefix.
      CHECK(r.T_target_source.matrix() == full.history[stop_at - 1].T_target_source.matrix());
    }
    // Fixed iterations firing at the iteration the callback cancels: the criterion is reported.
    RegistrationOptions f = o;
    f.criteria = ppcr::kCriterionFixed;
    f.expert.fixed_iterations = 3;
    f.on_iteration = [](const ppcr::IterationRecord& rec) { return rec.iteration < 3; };
    const RegistrationResult r = ppcr::align(source, target, f);
    CHECK(r.stop_reason == StopReason::kFixedIterations);
    CHECK(r.iterations == 3);
    CHECK(r.converged());
  }
}

TEST_CASE("a refused or unreachable input runs no iteration and calls no callback",
          "[reliability][bounds]") {
  Rng rng(24);
  const PointCloud target = rel_test::box_scene(rng, 300);
  RegistrationOptions o;
  int calls = 0;
  o.on_iteration = [&](const ppcr::IterationRecord&) {
    ++calls;
    return true;
  };
  const PointCloud empty;
  const std::vector<std::pair<const char*, RegistrationResult>> results = {
      {"empty source", ppcr::align(empty, target, o)},
      {"empty target", ppcr::align(target, empty, o)},
      {"source out of reach",
       ppcr::align(rel_test::transformed(target, rel_test::make_pose(Eigen::Vector3d::UnitZ(), 0.0,
                                                                     Eigen::Vector3d(0, 100, 0))),
                   target, o)}};
  RegistrationOptions bad = o;
  bad.radius = -1.0;
  const RegistrationResult refused = ppcr::align(target, target, bad);
  CHECK(refused.stop_reason == StopReason::kInvalidInput);
  CHECK(refused.iterations == 0);
  for (const auto& named : results) {
    INFO(named.first << ": " << describe(named.second));
    CHECK(named.second.iterations == 0);
    CHECK_FALSE(named.second.status.ok());
    CHECK(named.second.history.empty());
  }
  CHECK(calls == 0);
}
