// pair_normals.cpp - per-association normals from target and source normals (see header).
#include "pair_normals.hpp"

#include <cmath>
#include <cstdint>

#include "parallel.hpp"

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

}  // namespace

void compute_pair_normals(const AssociationTable& assoc,
                          const std::vector<PlanePoint>& target_points,
                          const std::vector<Eigen::Vector3d>& source_normals,
                          const Eigen::Matrix3d& R_target_source, int num_threads,
                          std::vector<Eigen::Vector3d>* pair_normals) {
  const std::size_t k = static_cast<std::size_t>(assoc.k);
  Eigen::Vector3d* out = pair_normals->data();
  parallel_for(num_threads, static_cast<std::ptrdiff_t>(assoc.count.size()), [&](std::ptrdiff_t i) {
    const std::size_t j = static_cast<std::size_t>(i);
    const std::size_t count = assoc.count[j];
    if (count == 0) return;
    const Eigen::Vector3d m = R_target_source * source_normals[j];  // zero stays zero
    const std::size_t first = j * k;
    const std::uint32_t* idx = &assoc.index[first];
    if (!(m.squaredNorm() > 0.0)) {  // no source normal: the target's own
      for (std::size_t q = 0; q < count; ++q) out[first + q] = target_points[idx[q]].n;
      return;
    }
    // n + s m with s the sign of n . m.
    auto oriented_sum = [&m](const Eigen::Vector3d& n) -> Eigen::Vector3d {
      return n.dot(m) >= 0.0 ? Eigen::Vector3d(n + m) : Eigen::Vector3d(n - m);
    };
    // One pair, n its target point's normal; a target point without a normal keeps 0.
    auto one_pair = [&](std::size_t q, const Eigen::Vector3d& n, bool has_normal) {
      if (!has_normal) {
        out[first + q] = n;
      } else {
        const Eigen::Vector3d sum = oriented_sum(n);
        out[first + q] = sum / std::sqrt(squared_length(sum.x(), sum.y(), sum.z()));
      }
    };
    std::size_t q = 0;
    // Two pairs per step, their coordinates in lanes (x0, x1), (y0, y1), (z0, z1): one square
    // root and three divisions serve both, the cost of this function (docs/PERFORMANCE.md). Each
    // lane computes sum / |sum| as one_pair does, squared_length() then a correctly
    // rounded root and divisions, and our targets do not contract a * b + c into a fused
    // multiply-add (-ffp-contract=off, CMakeLists.txt), so the bits are the same
    // (test_pair_normals; the same as Eigen's sum / sum.norm() where Eigen 3.4 vectorises).
    for (; q + 2 <= count; q += 2) {
      const Eigen::Vector3d& n0 = target_points[idx[q]].n;
      const Eigen::Vector3d& n1 = target_points[idx[q + 1]].n;
      const bool has0 = n0.squaredNorm() != 0.0, has1 = n1.squaredNorm() != 0.0;
      if (!(has0 && has1)) {  // rare: one at a time
        one_pair(q, n0, has0);
        one_pair(q + 1, n1, has1);
        continue;
      }
      const Eigen::Vector3d a = oriented_sum(n0), b = oriented_sum(n1);
      const Eigen::Array2d x(a.x(), b.x()), y(a.y(), b.y()), z(a.z(), b.z());
      const Eigen::Array2d norm = squared_length(x, y, z).sqrt();
      const Eigen::Array2d xn = x / norm, yn = y / norm, zn = z / norm;
      out[first + q] = Eigen::Vector3d(xn[0], yn[0], zn[0]);
      out[first + q + 1] = Eigen::Vector3d(xn[1], yn[1], zn[1]);
    }
    if (q < count) {
      const Eigen::Vector3d& n = target_points[idx[q]].n;
      one_pair(q, n, n.squaredNorm() != 0.0);
    }
  });
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
