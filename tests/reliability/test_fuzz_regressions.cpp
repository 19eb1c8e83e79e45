// fuzz_registration in the unit tests: the input decoder's layout (the seed corpus depends on
// it), saved inputs replayed (every crash the fuzzer finds is added to kRegressions with its
// diagnosis), and a seeded sweep of random inputs through the same decoder and invariants, so
// that the sanitizer build of the test suite covers the fuzz target's ground too.
#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "fuzz_registration_input.hpp"
#include "ppcr/registration.hpp"
#include "reliability_util.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;

struct Regression {
  const char* what;  // the finding and its fix
  Bytes input;
};

// Inputs saved from fuzz_registration runs (build-fuzz/fuzz/artifacts/registration/), with
// the finding each one showed (docs/RELIABILITY.md for the runs).
const std::vector<Regression> kRegressions = {
    {"a target of 60 identical points near 1e300 with a radius of 1e300: the internal unit was "
     "the radius, whose square overflowed, so the zero cost read inf x 0 = NaN in cloud units "
     "with an ok status; the unit is now at most 1e150",
     {0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0b, 0x00,
      0x00, 0x00, 0x00, 0x00, 0xfc, 0xff, 0xda, 0xfd, 0x00, 0xfc, 0x00, 0xfc, 0x61, 0xfd, 0x74,
      0x01, 0xc8, 0xdf, 0xff, 0x00, 0xfc, 0xc8, 0xfe, 0x06, 0xff, 0x89, 0xff, 0x00, 0xfc, 0x00,
      0xfc, 0x33, 0x03, 0x11, 0x01, 0xcc, 0x02, 0x00, 0xfc, 0xe2, 0xff, 0xda, 0xfd, 0x00, 0xfc,
      0x00, 0xfc, 0x61, 0xfd, 0x74, 0x01, 0xc8, 0xdf, 0xff, 0x00, 0xfc, 0xc8, 0xfe, 0x06, 0xff,
      0x89, 0xff, 0x00, 0xfc, 0x00, 0xfc, 0x33, 0x03, 0x11, 0x01, 0xcc, 0x02, 0x00, 0xfc, 0xb0,
      0xff, 0xed, 0x01, 0xb8, 0xff, 0x00, 0xfc, 0x00, 0xfc, 0xca, 0xff, 0x59, 0x03}},
};

/// The invariants' first violation on this input ("" when none); *iterations (when given) gets
/// the outer iterations the registration ran (0 when the input was refused before it).
std::string check(const Bytes& bytes, int* iterations = nullptr) {
  const ppcr_fuzz::RegistrationInput in =
      ppcr_fuzz::decode_registration_input(bytes.data(), bytes.size());
  const ppcr::RegistrationResult r = ppcr::align(in.source, in.target, in.options, in.T_initial);
  if (iterations != nullptr) *iterations = r.iterations;
  return rel_test::invariant_violation(r, in.options);
}

Bytes header() { return Bytes(ppcr_fuzz::kHeaderSize, 0); }

}  // namespace

TEST_CASE("fuzz input decoder: zero bytes give the library defaults with caps of 12",
          "[reliability][fuzz]") {
  const Bytes zeros = header();
  const ppcr_fuzz::RegistrationInput in =
      ppcr_fuzz::decode_registration_input(zeros.data(), zeros.size());
  const ppcr::RegistrationOptions defaults;
  const ppcr::RegistrationOptions& o = in.options;
  CHECK(o.radius == 1.0);
  CHECK(o.max_neighbours == defaults.max_neighbours);
  CHECK(o.dof == defaults.dof);
  CHECK(o.expert.scale_mode == ppcr::ScaleMode::kEM);
  CHECK(o.expert.scale == 0.0);
  CHECK(o.error_model == ppcr::ErrorModel::kPoint);
  CHECK(o.criteria == defaults.criteria);
  CHECK(o.max_iterations == 12);
  CHECK(o.expert.lm_max_iterations == 12);
  CHECK(o.expert.normal_neighbours == defaults.expert.normal_neighbours);
  CHECK(o.expert.plane_epsilon == Approx(defaults.expert.plane_epsilon).epsilon(0.03));
  CHECK(o.expert.cost_drop_patience == defaults.expert.cost_drop_patience);
  CHECK(o.expert.mse_patience == defaults.expert.mse_patience);
  CHECK(o.expert.em_coarse_patience == defaults.expert.em_coarse_patience);
  CHECK(o.expert.em_min_shrink == defaults.expert.em_min_shrink);
  CHECK(o.expert.cost_drop_threshold == defaults.expert.cost_drop_threshold);
  CHECK(o.source_voxel == 0.0);
  CHECK(o.expert.source_normals == defaults.expert.source_normals);
  CHECK(o.expert.reject_boundary == defaults.expert.reject_boundary);
  CHECK(o.num_threads == 1);
  CHECK(o.record_history);
  CHECK(in.source.empty());
  CHECK(in.target.empty());
  CHECK(in.T_initial.matrix() == Eigen::Matrix4d::Identity());
  CHECK(ppcr::validate(o).ok());
}

TEST_CASE("fuzz input decoder: the header offsets used by the seed corpus", "[reliability][fuzz]") {
  namespace f = ppcr_fuzz;
  Bytes b = header();
  b[f::kFlags0] = 1 | 4 | 16 | 64;  // plane, raw, 2 threads, derived target
  b[f::kFlags1] = 64 | 4;           // source normals, the boundary rule
  b[f::kMaxIterations] = 3;
  b[f::kLmMaxIterations] = 5;
  b[f::kMaxNeighbours] = 245;  // 1024
  b[f::kRadius] = 3;           // 2^3
  b[f::kDof] = static_cast<std::uint8_t>(-128);
  b[f::kDof + 1] = 1;         // special 1e300, times 5
  b[f::kSourceCode] = 30;     // unit 2^10
  b[f::kSourceCode + 1] = 1;  // offset 1e6
  b[f::kSourceCode + 2] = 2;  // two points
  b[f::kTargetCode + 2] = 1;  // plus one target point
  b[f::kTruePose + 3] = 64;   // T_gt translation x = 64 * unit / 64 (target unit 1)
  for (std::int16_t v : {1024, 0, 0, -32768, 0, 0, 0, 0, 512}) {
    b.push_back(static_cast<std::uint8_t>(v & 0xff));
    b.push_back(static_cast<std::uint8_t>((v >> 8) & 0xff));
  }
  const f::RegistrationInput in = f::decode_registration_input(b.data(), b.size());
  CHECK(in.options.error_model == ppcr::ErrorModel::kPlane);
  // bit6 flips the default's source normals.
  CHECK(in.options.expert.source_normals != ppcr::RegistrationOptions().expert.source_normals);
  // bit2 flips the default's boundary rule.
  CHECK(in.options.expert.reject_boundary != ppcr::RegistrationOptions().expert.reject_boundary);
  CHECK(in.options.expert.scale_mode == ppcr::ScaleMode::kRaw);
  CHECK(in.options.num_threads == 2);
  CHECK(in.options.max_iterations == 3);
  CHECK(in.options.expert.lm_max_iterations == 5);
  CHECK(in.options.max_neighbours == 1024);
  CHECK(in.options.radius == 8.0);
  CHECK(in.options.dof == ppcr::RegistrationOptions().dof * 1e300);
  REQUIRE(in.source.size() == 2);
  CHECK(in.source[0] == Eigen::Vector3d(1e6 + 1024.0, -0.5e6, 0.25e6));
  CHECK(std::isnan(in.source[1].x()));
  REQUIRE(in.target.size() == 3);  // two moved source points, then the target's own
  CHECK(in.target[0] == in.source[0] + Eigen::Vector3d(1, 0, 0));
  CHECK(in.target[2] == Eigen::Vector3d(0, 0, 0.5));
}

TEST_CASE("saved fuzz_registration inputs keep the invariants", "[reliability][fuzz]") {
  for (const Regression& r : kRegressions) {
    INFO(r.what);
    CHECK(check(r.input) == "");
  }
}

TEST_CASE("a seeded sweep of random fuzz_registration inputs keeps the invariants",
          "[reliability][fuzz]") {
  std::mt19937_64 rng(2024);
  std::uniform_int_distribution<int> byte(0, 255);
  int registered = 0;  // inputs that ran at least one outer iteration
  for (int i = 0; i < 300; ++i) {
    Bytes b = header();
    for (auto& v : b) v = static_cast<std::uint8_t>(byte(rng));
    // Keep most parameter bytes near the defaults (0) so that most runs get past validation.
    for (int at :
         {ppcr_fuzz::kRadius, ppcr_fuzz::kDof, ppcr_fuzz::kScale, ppcr_fuzz::kCostDropThreshold}) {
      if (byte(rng) < 192)
        b[static_cast<std::size_t>(at)] = static_cast<std::uint8_t>(byte(rng) % 8);
    }
    b[ppcr_fuzz::kSourceCode] = static_cast<std::uint8_t>(byte(rng) % 4);
    b[ppcr_fuzz::kTargetCode] = static_cast<std::uint8_t>(byte(rng) % 4);
    // Three inputs in four are shaped to reach the registration: the target is the source moved
    // by a small T_gt, no voxel filter, no offset, a small initial pose and a radius of 1 to 256
    // (fully random ones are mostly refused for want of correspondences or usable points).
    if (i % 4 != 0) {
      b[ppcr_fuzz::kFlags0] |= 0x40;
      b[ppcr_fuzz::kFlags1] &= static_cast<std::uint8_t>(~0x30);
      b[ppcr_fuzz::kSourceCode + 1] = 0;
      b[ppcr_fuzz::kTargetCode + 1] = 0;
      for (int j = 0; j < 6; ++j) {
        b[ppcr_fuzz::kInitialPose + j] = static_cast<std::uint8_t>(byte(rng) % 5);
        b[ppcr_fuzz::kTruePose + j] = static_cast<std::uint8_t>(byte(rng) % 5);
      }
      b[ppcr_fuzz::kRadius] = static_cast<std::uint8_t>(byte(rng) % 8);
    }
    const int points = 6 * (16 + byte(rng) % 112);
    for (int p = 0; p < points; ++p) b.push_back(static_cast<std::uint8_t>(byte(rng)));
    INFO("input " << i);
    int iterations = 0;
    CHECK(check(b, &iterations) == "");
    if (iterations > 0) ++registered;
  }
  // The sweep tests the registration only if its inputs get past validation: most must (208 of
  // the 300 when written; without the shaping above, 9).
  CHECK(registered >= 150);
}
