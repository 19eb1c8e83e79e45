// spatial_order.cpp - Z-order (Morton) sort of a cloud (see the header).
#include "association/spatial_order.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "common/parallel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// The 21 low bits of v spread to every third bit (bit i to bit 3i).
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// Applies the sorted keys' permutation in place (position i receives the point keys[i].index
// came from), to a and, if not null, to b: one cycle at a time, marking each position done in
// the top bit of its key's index (indices stay below 2^31).
constexpr std::uint32_t kDone = 0x80000000u;

void permute(Buffer<MortonKey>* keys, PointCloud* a, PointCloud* b) {
  for (std::size_t start = 0; start < keys->size(); ++start) {
    if ((*keys)[start].index & kDone) continue;
    const Eigen::Vector3d first_a = (*a)[start];
    const Eigen::Vector3d first_b = b != nullptr ? (*b)[start] : Eigen::Vector3d::Zero();
    std::size_t to = start;
    for (;;) {
      const std::size_t from = (*keys)[to].index;
      (*keys)[to].index |= kDone;
      if (from == start) {
        (*a)[to] = first_a;
        if (b != nullptr) (*b)[to] = first_b;
        break;
      }
      (*a)[to] = (*a)[from];
      if (b != nullptr) (*b)[to] = (*b)[from];
      to = from;
    }
  }
}

}  // namespace

void spatial_sort(PointCloud* a, PointCloud* b, SpatialSortScratch* scratch,
                  const Parallel* parallel) {
  assert(b == nullptr || b->size() == a->size());
  const std::size_t n = a->size();
  // The order is only an optimisation: a cloud too large for the 31-bit indices keeps its own.
  if (n < 2 || n >= kDone) return;
  Eigen::Vector3d lo = (*a)[0], hi = (*a)[0];
  for (const Eigen::Vector3d& p : *a) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  constexpr double kCells = static_cast<double>(1 << 21);
  const double extent = (hi - lo).maxCoeff();
  // All points equal (extent 0), or an extent beyond a double (points near +-DBL_MAX): nothing
  // to gain.
  if (!(extent > 0.0 && extent <= std::numeric_limits<double>::max())) return;
  // Cells of one size on every axis (a flat cloud keeps its neighbours close on the flat axis).
  // (p - lo) / extent is in [0, 1] also for a tiny extent, where kCells / extent would overflow.
  Buffer<MortonKey>& keys = scratch->keys;
  if (keys.capacity() < n) {  // exactly n: growing by resize() would double the capacity
    keys = {};
    keys.reserve(n);
  }
  keys.resize(n);
  parallel_for(parallel, static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t j) {
    const std::size_t i = static_cast<std::size_t>(j);
    const Eigen::Vector3d q = (((*a)[i] - lo) / extent * kCells).array().floor().min(kCells - 1.0);
    const std::uint64_t code = spread_bits(static_cast<std::uint64_t>(q.x())) |
                               spread_bits(static_cast<std::uint64_t>(q.y())) << 1 |
                               spread_bits(static_cast<std::uint64_t>(q.z())) << 2;
    keys[i] = MortonKey{code, static_cast<std::uint32_t>(i)};
  });
  // (code, index) keys are distinct: a total order, which any sort gives alike. With more than
  // one thread, the halves below and above the median key are sorted at once (nth_element
  // costs a fraction of the sort, and needs no memory).
  if (parallel != nullptr && parallel->threads() > 1) {
    const auto mid = keys.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(keys.begin(), mid, keys.end());
    parallel_for(parallel, 2, [&](std::ptrdiff_t half) {
      if (half == 0) {
        std::sort(keys.begin(), mid);
      } else {
        std::sort(mid, keys.end());
      }
    });
  } else {
    std::sort(keys.begin(), keys.end());
  }
  // Within a cell (equal codes), by coordinates, then index: exact duplicates become adjacent
  // (drop_duplicates), and the order does not depend on the input's. Runs are short but for
  // repeated points (a scanner's invalid returns at its origin) or a far outlier that widens the
  // cells; a run of m points costs O(m log m).
  const PointCloud& points = *a;
  auto by_coordinates = [&points](const MortonKey& l, const MortonKey& r) {
    const Eigen::Vector3d& p = points[l.index];
    const Eigen::Vector3d& q = points[r.index];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return l.index < r.index;
  };
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin + 1;
    while (end < n && keys[end].code == keys[begin].code) ++end;
    if (end - begin > 1) std::sort(keys.begin() + begin, keys.begin() + end, by_coordinates);
    begin = end;
  }
  permute(&keys, a, b);
}

std::size_t drop_duplicates(PointCloud* sorted) {
  if (sorted->empty()) return 0;
  std::size_t kept = 1;
  for (std::size_t i = 1; i < sorted->size(); ++i) {
    if ((*sorted)[i] != (*sorted)[kept - 1]) (*sorted)[kept++] = (*sorted)[i];
  }
  const std::size_t removed = sorted->size() - kept;
  sorted->resize(kept);
  return removed;
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
