// Determinism (issue #7): the same inputs give bit-identical results for 1, 2 and 3 threads and
// across runs, for both error models; registrations running concurrently in one process (each
// possibly multi-threaded) equal the sequential ones; a Registration reused for many align()
// calls, or re-targeted, equals fresh ones.
#include <catch2/catch.hpp>
#include <cstddef>
#include <string>
#include <thread>
#include <vector>

#include "ppcr/registration.hpp"
#include "reliability_util.hpp"
#include "result_checks.hpp"

using ppcr::ErrorModel;
using ppcr::PointCloud;
using ppcr::RegistrationOptions;
using ppcr::RegistrationResult;
using rel_test::Rng;

namespace {

const ErrorModel kModels[] = {ErrorModel::kPoint, ErrorModel::kPlane};

struct Pair {
  PointCloud source, target;
  Eigen::Isometry3d T_initial;
};

// Real-size clouds: an independently sampled source with noise and 10 % outliers, so that the
// sums over points really are long reductions split across threads.
Pair make_problem(std::uint64_t seed, std::size_t source_points, std::size_t target_points) {
  Rng rng(seed);
  Pair p;
  p.target = rel_test::box_scene(rng, target_points);
  PointCloud world = rel_test::box_scene(rng, source_points);
  std::normal_distribution<double> noise(0.0, 0.003);
  for (std::size_t i = 0; i < world.size(); ++i) {
    if (i % 10 == 0) {
      world[i] = Eigen::Vector3d(rel_test::uniform(rng, -1, 1), rel_test::uniform(rng, -1, 1),
                                 rel_test::uniform(rng, 0, 1));
    } else {
      world[i] += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    }
  }
  const Eigen::Isometry3d M = rel_test::make_pose(Eigen::Vector3d(0.2, 1.0, -0.4),
                                                  0.06 + 0.01 * static_cast<double>(seed % 5),
                                                  Eigen::Vector3d(0.05, -0.04, 0.03));
  p.source = rel_test::transformed(world, M.inverse());
  p.T_initial = rel_test::make_pose(Eigen::Vector3d::UnitZ(), 0.01, Eigen::Vector3d(0.01, 0, 0));
  return p;
}

RegistrationOptions options(ErrorModel model, int threads) {
  RegistrationOptions o;
  o.radius = 0.2;
  o.error_model = model;
  o.num_threads = threads;
  return o;
}

using test_checks::check_identical;

}  // namespace

TEST_CASE("bit-identical results for 1, 2 and 3 threads and across runs",
          "[reliability][determinism]") {
  const Pair p = make_problem(31, 4000, 10000);
  for (ErrorModel model : kModels) {
    INFO("model " << static_cast<int>(model));
    const RegistrationResult one = ppcr::align(p.source, p.target, options(model, 1), p.T_initial);
    INFO(rel_test::describe(one));
    REQUIRE(one.status.ok());
    REQUIRE(one.iterations > 5);  // a real run, not a one-step exit
    for (int threads : {1, 2, 3}) {
      INFO(threads << " thread(s), second run");
      check_identical(one, ppcr::align(p.source, p.target, options(model, threads), p.T_initial));
    }
  }
}

TEST_CASE("concurrent registrations in one process equal the sequential ones",
          "[reliability][determinism]") {
  // Four registrations at once: two error models x two problems, each with 2 threads
  // inside its std::thread.
  const Pair a = make_problem(41, 2000, 5000);
  const Pair b = make_problem(42, 2000, 5000);
  struct Job {
    const Pair* pair;
    RegistrationOptions options;
    RegistrationResult sequential, concurrent;
  };
  std::vector<Job> jobs;
  for (ErrorModel model : kModels) {
    for (const Pair* pair : {&a, &b}) jobs.push_back({pair, options(model, 2), {}, {}});
  }
  for (Job& j : jobs) {
    j.sequential = ppcr::align(j.pair->source, j.pair->target, j.options, j.pair->T_initial);
  }
  std::vector<std::thread> threads;
  for (Job& j : jobs) {
    threads.emplace_back([&j] {
      j.concurrent = ppcr::align(j.pair->source, j.pair->target, j.options, j.pair->T_initial);
    });
  }
  for (std::thread& t : threads) t.join();
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    INFO("job " << i);
    check_identical(jobs[i].sequential, jobs[i].concurrent);
  }
  // The four problems really differ (a shared buffer would show as equal results).
  CHECK(jobs[0].sequential.T_target_source.matrix() != jobs[1].sequential.T_target_source.matrix());
  CHECK(jobs[0].sequential.T_target_source.matrix() != jobs[2].sequential.T_target_source.matrix());
}

TEST_CASE("one Registration object per thread, each aligning several sources",
          "[reliability][determinism]") {
  const Pair p = make_problem(51, 2000, 6000);
  const RegistrationOptions o = options(ErrorModel::kPlane, 1);
  std::vector<PointCloud> sources;
  for (std::size_t n : {2000u, 700u, 1500u}) {
    sources.emplace_back(p.source.begin(), p.source.begin() + static_cast<std::ptrdiff_t>(n));
  }
  std::vector<RegistrationResult> expected;
  for (const PointCloud& s : sources) expected.push_back(ppcr::align(s, p.target, o, p.T_initial));
  std::vector<std::vector<RegistrationResult>> got(3);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < got.size(); ++t) {
    threads.emplace_back([&, t] {
      ppcr::Registration reg(o);
      if (!reg.set_target(p.target).ok()) return;
      for (const PointCloud& s : sources) got[t].push_back(reg.align(s, p.T_initial));
    });
  }
  for (std::thread& t : threads) t.join();
  for (std::size_t t = 0; t < got.size(); ++t) {
    REQUIRE(got[t].size() == sources.size());
    for (std::size_t i = 0; i < sources.size(); ++i) {
      INFO("thread " << t << ", source " << i);
      check_identical(expected[i], got[t][i]);
    }
  }
}

TEST_CASE("a reused or re-targeted Registration equals fresh ones", "[reliability][determinism]") {
  const Pair p = make_problem(61, 2500, 6000);
  const Pair q = make_problem(62, 1200, 4000);
  for (ErrorModel model : kModels) {
    INFO("model " << static_cast<int>(model));
    const RegistrationOptions o = options(model, 2);
    ppcr::Registration reg(o);
    REQUIRE(reg.set_target(p.target).ok());
    const Eigen::Isometry3d other_guess =
        rel_test::make_pose(Eigen::Vector3d::UnitX(), -0.02, Eigen::Vector3d(0, 0.02, -0.01));
    // Different sizes and guesses in a row, then the first again.
    check_identical(ppcr::align(p.source, p.target, o, p.T_initial),
                    reg.align(p.source, p.T_initial));
    check_identical(ppcr::align(q.source, p.target, o, other_guess),
                    reg.align(q.source, other_guess));
    check_identical(ppcr::align(p.source, p.target, o, p.T_initial),
                    reg.align(p.source, p.T_initial));
    // A new target replaces the old one completely (tree, normals, origin).
    REQUIRE(reg.set_target(q.target).ok());
    check_identical(ppcr::align(q.source, q.target, o, q.T_initial),
                    reg.align(q.source, q.T_initial));
    // A failed set_target leaves no stale target behind.
    CHECK_FALSE(reg.set_target(PointCloud(2, Eigen::Vector3d::Zero())).ok());
    const RegistrationResult stale = reg.align(q.source);
    CHECK(stale.stop_reason == ppcr::StopReason::kInvalidInput);
    REQUIRE(reg.set_target(q.target).ok());
    check_identical(ppcr::align(q.source, q.target, o, q.T_initial),
                    reg.align(q.source, q.T_initial));
  }
}
