// pair_normals.hpp - per-pair normals of the plane model with source normals
// (ExpertOptions::source_normals).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "model/normal_equations.hpp"
#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// a . b summed as (a_x b_x + a_y b_y) + a_z b_z, written out (not Eigen's dot(), whose order
/// depends on whether it vectorises doubles), so that the plane pass's one-point and four-point
/// paths (four_points.hpp) sum in the same order in every build.
inline double dot_in_order(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a.x() * b.x() + a.y() * b.y()) + a.z() * b.z();
}

/// a of a pair's Omega = a I + n n^T (PairNormal): epsilon with a normal, else 1.
inline double pair_isotropic(const PairNormal& pn, double epsilon) {
  return pn.q > 0.0 ? epsilon : 1.0;
}

/// The normals of one source point's pairs, formed in the plane pass (normal_equations.cpp) from
/// PairNormalSource: for its i-th pair (target point y = idx[i], normal n = target_points[y].n)
/// and m = R m_j, its source normal in the target frame at the association's rotation R,
///   s = n + sign(n . m) m   (sign +1 when n . m >= 0),
/// the mean direction of the two surfaces' normals (the sign flips the source normal onto the
/// target's side: PCA normals have no sign; |s| >= 1, never degenerate). A source point
/// without a normal (m = 0) has s = n; a target point without one (n = 0), s = 0 and q = 0.
/// Writes out[0..count). Formed per pass rather than stored per pair (24 B x k per source point
/// less, docs/PERFORMANCE.md); within an inner solve the later passes may form them from the
/// memo the first one wrote (below).
/// If memo is not null, also writes memo[0..count): each pair's q with, in its sign bit, whether
/// its s took -m (what pair_normals_from_memo() needs to form the same s and q again).
void pair_normals_of_point(const Eigen::Vector3d& m, const std::uint32_t* idx, std::size_t count,
                           const PlanePoint* target_points, PairNormal* out,
                           double* memo = nullptr);

/// The same out[0..count) as pair_normals_of_point() with the same m, idx and target points, to
/// the bit, from the memo it wrote: no dot product, squared length or division.
void pair_normals_from_memo(const Eigen::Vector3d& m, const std::uint32_t* idx, std::size_t count,
                            const PlanePoint* target_points, const double* memo, PairNormal* out);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
