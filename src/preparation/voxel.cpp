// voxel.cpp - voxel-grid downsampling: the centroid of the points of each occupied voxel.
#include "ppcr/voxel.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "common/format.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

Status voxel_downsample(const PointCloud& cloud, double leaf_size, PointCloud* out) {
  if (!(std::isfinite(leaf_size) && leaf_size > 0.0)) {
    return Status(StatusCode::kInvalidArgument,
                  "voxel leaf size must be finite and > 0, got " + detail::num(leaf_size));
  }
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-HUGE_VAL);
  std::size_t finite = 0;
  for (const Eigen::Vector3d& p : cloud) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    ++finite;
  }
  out->clear();
  if (finite == 0) return Status::Ok();

  // 21 bits per axis pack a cell index into one 64-bit key. The cell index of a point is
  // floor((p - lo) * inv_leaf), rounded exactly as below; every rounding step is monotone, so the
  // index of hi bounds every index, and checking it keeps each index within its 21-bit field.
  // (Checking floor((hi - lo) / leaf) instead could accept an index of 2^21, which would spill
  // into the next field and merge unrelated voxels.) A leaf so small that 1 / leaf overflows
  // gives cells of +inf or NaN (0 * inf), refused too.
  constexpr double kMaxCells = static_cast<double>(1 << 21);
  const double inv_leaf = 1.0 / leaf_size;
  const Eigen::Vector3d cells = ((hi - lo) * inv_leaf).array().floor() + 1.0;
  if (!(cells.array() <= kMaxCells).all()) {
    return Status(StatusCode::kInvalidArgument, "voxel leaf size " + detail::num(leaf_size) +
                                                    " is too small for a cloud " + "spanning " +
                                                    detail::num((hi - lo).maxCoeff()) +
                                                    " units: more than 2^21 cells along an axis");
  }

  struct Cell {
    Eigen::Vector3d sum;
    std::size_t count;
  };
  std::vector<Cell> sums;
  std::unordered_map<std::uint64_t, std::size_t> index_of_key;
  index_of_key.reserve(finite / 4 + 16);
  for (const Eigen::Vector3d& p : cloud) {
    if (!p.allFinite()) continue;
    const Eigen::Vector3d q = ((p - lo) * inv_leaf).array().floor();
    const std::uint64_t key = (static_cast<std::uint64_t>(q.x()) << 42) |
                              (static_cast<std::uint64_t>(q.y()) << 21) |
                              static_cast<std::uint64_t>(q.z());
    auto inserted = index_of_key.emplace(key, sums.size());
    if (inserted.second) {
      sums.push_back({p, 1});
    } else {
      Cell& c = sums[inserted.first->second];
      c.sum += p;
      ++c.count;
    }
  }
  out->reserve(sums.size());
  for (const Cell& c : sums) out->push_back(c.sum / static_cast<double>(c.count));
  return Status::Ok();
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
