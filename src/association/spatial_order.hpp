// spatial_order.hpp - clouds reordered along a Z-order (Morton) curve, so that points near in
// space are near in memory.
//
// The registration visits the target through its k-d tree and gathers each association's target
// point at random: in the order a scanner or a voxel filter leaves them, a source point's
// neighbours lie scattered over the target array, and consecutive source points share few cache
// lines. Along a Z-order curve of the bounding box's cells, most of a point's neighbours lie a
// few entries apart, and consecutive source points have mostly the same neighbours
// (docs/PERFORMANCE.md). The order is internal; it changes results only as any order does: sums
// are taken in another order (rounding), and among neighbours at exactly equal distances the
// k-d tree's visiting order decides which are kept. The Z-order makes both independent of the
// order of the input points (equal points aside: drop_duplicates() keeps one of them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/buffer.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;  // parallel.hpp

/// A point's sort key: its Morton code, then its index (distinct: a total order).
struct MortonKey {
  std::uint64_t code;
  std::uint32_t index;
  bool operator<(const MortonKey& o) const {
    return code < o.code || (code == o.code && index < o.index);
  }
};

/// The buffer of spatial_sort (16 B per point), kept between calls so that a cloud of the same
/// size reuses it. A Buffer: a larger cloud's keys are first written on the threads of `parallel`.
struct SpatialSortScratch {
  Buffer<MortonKey> keys;
};

/// Reorders *a (and *b, of the same size, by the same permutation, if not null) in place by the
/// Morton code of each point of *a over *a's bounding box, in cubic cells of 1 / 2^21 of its
/// longest side, ties (one cell) by x, then y, then z, then index: equal points end up adjacent,
/// in their input order. Points must be finite; a cloud of fewer than 2 or 2^31 or more points,
/// of identical points or whose extent overflows a double is left as it is. Allocation-free once
/// the scratch is as large. Parallel on the threads of `parallel` (null: the calling thread); the
/// order does not depend on their number.
void spatial_sort(PointCloud* a, PointCloud* b, SpatialSortScratch* scratch,
                  const Parallel* parallel = nullptr);

/// Removes the exact duplicates of a cloud in spatial_sort()'s order, where they are adjacent:
/// of each run of equal points (==, so -0 equals +0) the first is kept. Returns how many were
/// removed. In place, order kept, O(n); a cloud spatial_sort() left as it was (an extent beyond a
/// double, 2^31 points or more) loses only its adjacent duplicates.
std::size_t drop_duplicates(PointCloud* sorted);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
