// pair_normals.cpp - per-pair normals from target and source normals (see header).
#include "pair_normals.hpp"

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
// so a branch on the sign of n . m would be mispredicted about every other pair (written as a
// branch, the pass took 2.5-4 % longer on the lidar set). x + (-y) is x - y to the bit.
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

}  // namespace

void pair_normals_of_point(const Eigen::Vector3d& m, const std::uint32_t* idx, std::size_t count,
                           const PlanePoint* target_points, PairNormal* out) {
  // s = n + sign(n . m) m; a zero m leaves n, a zero n gives 0 (q = 0 below).
  auto axis = [&m](const Eigen::Vector3d& n) -> Eigen::Vector3d {
    if (n.squaredNorm() == 0.0) return Eigen::Vector3d::Zero();
    return n + negated_if(!(n.dot(m) >= 0.0), m);
  };
  auto inverse_sq = [](const Eigen::Vector3d& v) {
    const double sq = squared_length(v.x(), v.y(), v.z());
    return sq > 0.0 ? 1.0 / sq : 0.0;
  };
  std::size_t i = 0;
  // Two pairs per step, their squared lengths in lanes: one division serves both. Each lane
  // computes 1 / squared_length() as inverse_sq does, correctly rounded, so the bits are the
  // same whatever a pair's place in its list (test_pair_normals).
  for (; i + 2 <= count; i += 2) {
    const Eigen::Vector3d a = axis(target_points[idx[i]].n);
    const Eigen::Vector3d b = axis(target_points[idx[i + 1]].n);
    const Eigen::Array2d sq = squared_length(
        Eigen::Array2d(a.x(), b.x()), Eigen::Array2d(a.y(), b.y()), Eigen::Array2d(a.z(), b.z()));
    const Eigen::Array2d q = (sq > 0.0).select(1.0 / sq, 0.0);  // 0: no target normal
    out[i] = {a, q[0]};
    out[i + 1] = {b, q[1]};
  }
  if (i < count) {
    const Eigen::Vector3d a = axis(target_points[idx[i]].n);
    out[i] = {a, inverse_sq(a)};
  }
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
