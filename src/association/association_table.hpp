// association_table.hpp - data association: for each source point, transformed by the current pose,
// up to k target points within the radius (paper Sec. 3.1), in a fixed-stride table.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "association/kdtree.hpp"
#include "common/buffer.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;  // parallel.hpp

/// Slot m < count[j] of source point j holds its m-th nearest target point within the radius,
/// index[j * k + m] (into the target). Ties in distance are ordered by index on every path (the
/// neighbour cache and associate()), so slot 0 is the same point whichever path wrote the row.
/// The distances are not kept (each user computes its own residual: 8 B per slot less). Sized
/// once by resize(), which leaves every point without pairs.
struct AssociationTable {
  int k = 0;
  Buffer<std::uint32_t> index;       // written by each association before it is read
  std::vector<std::uint16_t> count;  // k <= kMaxNeighbours fits in 16 bits
  // Rows left out of the solve (Associator::find: beyond the target's boundary, boundary.hpp):
  // left_out[j] != 0 while any_left_out (sized by the leaving out, not by resize(): empty while
  // no row is left out). A left-out row keeps its slots and count (the neighbour cache's state),
  // but pairs and matched do not count it and the passes skip it.
  std::vector<std::uint8_t> left_out;
  bool any_left_out = false;
  std::size_t pairs = 0;    // sum of count over the rows used
  std::size_t matched = 0;  // rows used with count > 0
  // The rows left out (each with count > 0) and their pairs: with pairs and matched, every row's.
  std::size_t left_out_pairs = 0;
  std::size_t left_out_rows = 0;

  static constexpr int kMaxNeighbours = 1024;

  void resize(std::size_t source_points, int neighbours);
  /// Sets pairs and matched from count and left_out (integer sums: exact in any order).
  void recount();
  /// Every row's pairs and rows with pairs, the left-out ones included.
  std::size_t all_pairs() const { return pairs + left_out_pairs; }
  std::size_t all_matched() const { return matched + left_out_rows; }
  /// Whether row j is used: it has pairs and is not left out.
  bool used(std::size_t j) const { return count[j] > 0 && !(any_left_out && left_out[j] != 0); }
};

/// Fills table for the source points moved by T_target_source (both in the frames the tree and
/// source are expressed in). Parallel over source points; the result does not depend on the
/// thread count. Allocation-free once the table is sized.
void associate(const KdTree& target_tree, const PointCloud& source,
               const Eigen::Isometry3d& T_target_source, double radius_sq, const Parallel* parallel,
               AssociationTable* table);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
