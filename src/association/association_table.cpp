// association_table.cpp - radius-limited kNN of every transformed source point.
#include "association/association_table.hpp"

#include <cassert>
#include <utility>

#include "common/parallel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

void AssociationTable::resize(std::size_t source_points, int neighbours) {
  k = neighbours;
  index.resize(source_points * static_cast<std::size_t>(neighbours));
  count.resize(source_points);
  any_left_out = false;
  pairs = matched = left_out_pairs = left_out_rows = 0;
}

void AssociationTable::recount() {
  pairs = matched = left_out_pairs = left_out_rows = 0;
  for (std::size_t j = 0; j < count.size(); ++j) {
    if (any_left_out && left_out[j] != 0) {
      left_out_pairs += count[j];
      ++left_out_rows;
    } else {
      pairs += count[j];
      matched += (count[j] > 0);
    }
  }
}

void associate(const KdTree& target_tree, const PointCloud& source,
               const Eigen::Isometry3d& T_target_source, double radius_sq, const Parallel* parallel,
               AssociationTable* table) {
  const int k = table->k;
  assert(k <= AssociationTable::kMaxNeighbours);  // the query's distances on the stack
  const Eigen::Matrix3d R = T_target_source.linear();
  const Eigen::Vector3d t = T_target_source.translation();
  parallel_for(parallel, static_cast<std::ptrdiff_t>(source.size()), [&](std::ptrdiff_t j) {
    const std::size_t slot = static_cast<std::size_t>(j) * static_cast<std::size_t>(k);
    const Eigen::Vector3d p = R * source[static_cast<std::size_t>(j)] + t;
    double dist_sq[AssociationTable::kMaxNeighbours];  // the query's, not kept
    std::uint32_t* row = &table->index[slot];
    const int n = target_tree.radius_knn(p, k, radius_sq, row, dist_sq);
    // The query lists points tied in distance in its visit order; the table lists them by index,
    // as the neighbour cache does (AssociationTable).
    for (int m = 1; m < n; ++m) {
      for (int i = m; i > 0 && dist_sq[i - 1] == dist_sq[i] && row[i - 1] > row[i]; --i) {
        std::swap(row[i - 1], row[i]);
      }
    }
    table->count[static_cast<std::size_t>(j)] = static_cast<std::uint16_t>(n);
  });
  table->recount();
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
