// pair_normals.cpp - per-pair normals from target and source normals (see header).
#include "model/pair_normals.hpp"

#include <cmath>
#include <cstring>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// |(x, y, z)|^2 summed as (x^2 + y^2) + z^2, for one pair (double) or two in lanes
// (Eigen::Array2d): one expression, so that both forms sum in the same order (written out:
// Eigen's norm() sums in another order where it does not vectorise doubles in pairs).
template <class T>
T squared_length(const T& x, const T& y, const T& z) {
  return (x * x + y * y) + z * z;
}

// v with every sign bit flipped when `flip`, else v, without a branch: PCA normals have no sign,
// so a branch on the sign of n . m would be mispredicted about every other pair
// (docs/PERFORMANCE.md). x + (-y) is x - y to the bit.
inline Eigen::Vector3d negated_if(bool flip, const Eigen::Vector3d& v) {
  const std::uint64_t sign = static_cast<std::uint64_t>(flip) << 63;
  Eigen::Vector3d out;
  for (int a = 0; a < 3; ++a) {
    std::uint64_t bits;
    std::memcpy(&bits, &v[a], sizeof bits);
    bits ^= sign;
    std::memcpy(&out[a], &bits, sizeof bits);
  }
  return out;
}

// The memo of a pair: q (>= 0) with `flip` in its sign bit.
inline double with_flip(double q, bool flip) { return std::copysign(q, flip ? -1.0 : 1.0); }

}  // namespace

void pair_normals_of_point(const Eigen::Vector3d& m, const std::uint32_t* idx, std::size_t count,
                           const PlanePoint* target_points, PairNormal* out, double* memo) {
  // s = n + sign(n . m) m; a zero m leaves n, a zero n gives 0 (q = 0 below).
  auto axis = [&m](const Eigen::Vector3d& n, bool* flip) -> Eigen::Vector3d {
    *flip = false;
    if (n.squaredNorm() == 0.0) return Eigen::Vector3d::Zero();
    *flip = !(dot_in_order(n, m) >= 0.0);
    return n + negated_if(*flip, m);
  };
  auto inverse_sq = [](const Eigen::Vector3d& v) {
    const double sq = squared_length(v.x(), v.y(), v.z());
    return sq > 0.0 ? 1.0 / sq : 0.0;
  };
  std::size_t i = 0;
  bool flip_a, flip_b;
  // Two pairs per step, their squared lengths in lanes: one division serves both. Each lane
  // computes 1 / squared_length() as inverse_sq does, correctly rounded, so the bits are the
  // same whatever a pair's place in its list (test_pair_normals).
  for (; i + 2 <= count; i += 2) {
    const Eigen::Vector3d a = axis(target_points[idx[i]].n, &flip_a);
    const Eigen::Vector3d b = axis(target_points[idx[i + 1]].n, &flip_b);
    const Eigen::Array2d sq = squared_length(
        Eigen::Array2d(a.x(), b.x()), Eigen::Array2d(a.y(), b.y()), Eigen::Array2d(a.z(), b.z()));
    const Eigen::Array2d q = (sq > 0.0).select(1.0 / sq, 0.0);  // 0: no target normal
    out[i] = {a, q[0]};
    out[i + 1] = {b, q[1]};
    if (memo != nullptr) {
      memo[i] = with_flip(q[0], flip_a);
      memo[i + 1] = with_flip(q[1], flip_b);
    }
  }
  if (i < count) {
    const Eigen::Vector3d a = axis(target_points[idx[i]].n, &flip_a);
    out[i] = {a, inverse_sq(a)};
    if (memo != nullptr) memo[i] = with_flip(out[i].q, flip_a);
  }
}

void pair_normals_from_memo(const Eigen::Vector3d& m, const std::uint32_t* idx, std::size_t count,
                            const PlanePoint* target_points, const double* memo, PairNormal* out) {
  for (std::size_t i = 0; i < count; ++i) {
    const bool flip = std::signbit(memo[i]);
    const double q = std::fabs(memo[i]);
    // q = 0 only without a target normal: with one, |s|^2 = |n|^2 + |m|^2 + 2 |n . m| >= 1.
    out[i] = q == 0.0 ? PairNormal{Eigen::Vector3d::Zero(), 0.0}
                      : PairNormal{target_points[idx[i]].n + negated_if(flip, m), q};
  }
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
