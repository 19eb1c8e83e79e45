// alignment_quality.cpp - see alignment_quality.hpp.
#include "quality/alignment_quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "common/parallel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

constexpr std::size_t kBlock = 1024;

// Sums over points [0, n) in blocks of kBlock, deterministic for any thread count: body(begin,
// end, out) writes a block's W partial sums to out[0 .. W), which are then added block by block
// in order. scratch holds the partial sums (kept by the caller).
template <std::size_t W, class Body>
std::array<double, W> block_sums(const Parallel* parallel, std::size_t n,
                                 std::vector<double>* scratch, Body&& body) {
  const std::size_t n_blocks = block_count(n, kBlock);
  scratch->resize(W * n_blocks);
  double* blocks = scratch->data();
  parallel_for_blocks(parallel, n, kBlock,
                      [&](std::ptrdiff_t b, std::size_t begin, std::size_t end) {
                        body(begin, end, blocks + W * static_cast<std::size_t>(b));
                      });
  std::array<double, W> total{};
  for (std::size_t b = 0; b < n_blocks; ++b) {
    for (std::size_t w = 0; w < W; ++w) total[w] += blocks[W * b + w];
  }
  return total;
}

struct Sums {
  double matched = 0.0;  // counts, exact in a double up to 2^53
  double near = 0.0;     // matched within near_sq
  double close = 0.0;    // of those, on the target's surface (SurfaceTest)
  double dist_sq = 0.0;
};
constexpr std::size_t kSums = 4;

// SurfaceTest with its lengths squared once.
struct SurfaceTestSq {
  explicit SurfaceTestSq(const SurfaceTest& t)
      : close_sq(t.close_distance * t.close_distance),
        // Never stricter than the point test: a reach below close_distance (few fit neighbours
        // on a grid) does not exclude a point close_distance from y.
        reach_sq(std::max(t.reach * t.reach, close_sq)),
        planes(t.planes) {}
  double close_sq, reach_sq;
  const Buffer<PlanePoint>* planes;
};

// Whether p, whose nearest target point is y = points[index] at squared distance d_sq, is on the
// target's surface (SurfaceTest).
bool on_surface(const SurfaceTestSq& t, std::uint32_t index, const Eigen::Vector3d& p,
                double d_sq) {
  if (t.planes == nullptr) return d_sq <= t.close_sq;
  const PlanePoint& q = (*t.planes)[index];
  if (q.n.isZero()) return d_sq <= t.close_sq;  // y has no normal: the point test
  const double along = q.n.dot(p - q.y);
  return along * along <= t.close_sq && d_sq <= t.reach_sq;
}

// Nearest point of `tree` (built over `indexed`) within radius of each T * points[i], whether it
// is within near_sq and whether a near point is on the surface. Summed per block, then in order.
// Each query is seeded (kdtree.hpp, "Seeded queries") by the previous point's nearest, a real
// indexed point: in the clouds' Z-order consecutive points lie close, so the bound prunes from
// the first leaf on; the result is the unseeded query's, ties included.
Sums nearest_within(const KdTree& tree, const PointCloud& indexed, const PointCloud& points,
                    const Eigen::Isometry3d& T, double radius_sq, double near_sq,
                    const SurfaceTestSq& surface, const Parallel* parallel,
                    std::vector<double>* scratch) {
  const std::array<double, kSums> t = block_sums<kSums>(
      parallel, points.size(), scratch, [&](std::size_t begin, std::size_t end, double* out) {
        Sums s;
        bool seeded = false;  // whether `index` holds the previous point's nearest
        std::uint32_t index = 0;
        for (std::size_t i = begin; i < end; ++i) {
          double d_sq;
          const Eigen::Vector3d p = T * points[i];
          const double seed_sq = seeded ? seed_bound_sq(p, indexed, &index, 1)
                                        : std::numeric_limits<double>::infinity();
          seeded = seeded_radius_knn(tree, p, 1, seed_sq, radius_sq, &index, &d_sq).found == 1;
          if (seeded) {
            s.matched += 1.0;
            s.dist_sq += d_sq;
            if (d_sq > near_sq) continue;
            s.near += 1.0;
            s.close += on_surface(surface, index, p, d_sq) ? 1.0 : 0.0;
          }
        }
        out[0] = s.matched;
        out[1] = s.near;
        out[2] = s.close;
        out[3] = s.dist_sq;
      });
  Sums total;
  total.matched = t[0];
  total.near = t[1];
  total.close = t[2];
  total.dist_sq = t[3];
  return total;
}

// How many of the points T * points[i] have a point of `tree` (built over `indexed`) within
// radius: any one, not the nearest, so the point found for the previous point is tried first (in
// Z-order consecutive points lie close) and a query is made only when it is beyond the radius.
double count_within(const KdTree& tree, const PointCloud& indexed, const PointCloud& points,
                    const Eigen::Isometry3d& T, double radius_sq, const Parallel* parallel,
                    std::vector<double>* scratch) {
  return block_sums<1>(
      parallel, points.size(), scratch, [&](std::size_t begin, std::size_t end, double* out) {
        double count = 0.0;
        bool found = false;  // whether `index` holds the previous point's find
        std::uint32_t index = 0;
        for (std::size_t i = begin; i < end; ++i) {
          const Eigen::Vector3d p = T * points[i];
          if (!(found && squared_distance(p.data(), indexed[index].data()) <= radius_sq)) {
            double d_sq;
            found = tree.radius_knn(p, 1, radius_sq, &index, &d_sq) == 1;
          }
          count += found ? 1.0 : 0.0;
        }
        out[0] = count;
      })[0];
}

}  // namespace

AlignmentQuality measure_alignment(const KdTree& target_tree, const PointCloud& target,
                                   const PointCloud& source, const KdTree* source_tree,
                                   const Eigen::Isometry3d& T_target_source, double radius,
                                   double near_distance, const SurfaceTest& surface,
                                   const Parallel* parallel, std::vector<double>* scratch) {
  AlignmentQuality q;
  if (source.empty() || target.empty()) return q;
  const double radius_sq = radius * radius;
  const double near_sq = near_distance * near_distance;
  const SurfaceTestSq surface_sq(surface);
  const Sums s = nearest_within(target_tree, target, source, T_target_source, radius_sq, near_sq,
                                surface_sq, parallel, scratch);
  q.fitness = s.matched / static_cast<double>(source.size());
  q.inlier_rmse = s.matched > 0.0 ? std::sqrt(s.dist_sq / s.matched) : 0.0;
  q.close_fraction = s.near > 0.0 ? s.close / s.near : 0.0;
  q.overlap = q.fitness;
  if (source_tree != nullptr) {
    const double back = count_within(*source_tree, source, target, T_target_source.inverse(),
                                     radius_sq, parallel, scratch);
    q.overlap = std::min(q.fitness, back / static_cast<double>(target.size()));
  }
  return q;
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
