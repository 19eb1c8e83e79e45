// random.hpp - the seeded random numbers of ppcr_synthetic (internal).
//
// std::mt19937_64 is specified bit for bit by the C++ standard, but std::uniform_real_distribution
// and std::normal_distribution are not (libstdc++, libc++ and MSVC give different numbers). So the
// conversions to doubles are ours: 53-bit uniforms and the Box-Muller transform.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

/// Independent streams derived from the user's seed (one per use), so that changing one option
/// (e.g. the noise) does not change the numbers drawn for another (e.g. the scene layout).
enum class Stream : std::uint64_t {
  kScene = 1,
  kPoses = 2,
  kSourceNoise = 3,
  kTargetNoise = 4,
  kSourceOutliers = 5,
  kTargetOutliers = 6,
  kSurfaceSamples = 7,
  kTrajectory = 8,        // a sequence's path: its start, direction and sway phases
  kSequenceNoise = 9,     // a sequence's range noise, one sub-stream per scan
  kSequenceOutliers = 10  // a sequence's outliers, one sub-stream per scan
};

/// SplitMix64 finaliser (Steele, Lea and Flood 2014): a bijective mixing of 64 bits.
inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

inline std::uint64_t stream_seed(std::uint64_t seed, Stream stream) {
  return splitmix64(splitmix64(seed) ^ static_cast<std::uint64_t>(stream));
}

class Rng {
 public:
  Rng(std::uint64_t seed, Stream stream) : engine_(stream_seed(seed, stream)) {}
  /// Sub-stream `index` of a stream (scan `index` of a sequence): independent of the others, so
  /// a scan's numbers do not depend on how many scans came before it.
  Rng(std::uint64_t seed, Stream stream, std::uint64_t index)
      : engine_(splitmix64(stream_seed(seed, stream) ^ splitmix64(index))) {}

  /// Uniform in [0, 1): the top 53 bits of one 64-bit draw.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  /// Standard normal deviate by the Box-Muller transform; the second deviate of each pair is
  /// kept for the next call.
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]: log(u1) is finite
    const double u2 = uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    const double angle = 2.0 * kPi * u2;
    spare_ = radius * std::sin(angle);
    has_spare_ = true;
    return radius * std::cos(angle);
  }

  /// Uniform on the unit sphere (z uniform in [-1, 1], azimuth uniform: Archimedes).
  Eigen::Vector3d unit_vector() {
    const double z = uniform(-1.0, 1.0);
    const double azimuth = uniform(0.0, 2.0 * kPi);
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Eigen::Vector3d(rho * std::cos(azimuth), rho * std::sin(azimuth), z);
  }

  /// true with probability p.
  bool bernoulli(double p) { return uniform() < p; }

  static constexpr double kPi = 3.14159265358979323846;

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
