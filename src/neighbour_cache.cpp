// neighbour_cache.cpp - see neighbour_cache.hpp for the certificate.
#include "neighbour_cache.hpp"

#include <cmath>

#include "parallel.hpp"

namespace ppcr {
namespace detail {
namespace {

// Re-ranks candidates idx[0..n) by squared distance to p into the table slots out_idx/out_d
// (ascending; ties by target index), keeping at most k within radius_sq. Returns the count.
int rerank(const PointCloud& target, const Eigen::Vector3d& p, const std::uint32_t* idx, int n,
           int k, double radius_sq, std::uint32_t* out_idx, double* out_d) {
  int held = 0;
  for (int c = 0; c < n; ++c) {
    const double d = (target[idx[c]] - p).squaredNorm();
    if (!(d <= radius_sq)) continue;
    if (held == k && !(d < out_d[k - 1] || (d == out_d[k - 1] && idx[c] < out_idx[k - 1]))) {
      continue;
    }
    int i = held < k ? held++ : k - 1;
    while (i > 0 && (out_d[i - 1] > d || (out_d[i - 1] == d && out_idx[i - 1] > idx[c]))) {
      out_d[i] = out_d[i - 1];
      out_idx[i] = out_idx[i - 1];
      --i;
    }
    out_d[i] = d;
    out_idx[i] = idx[c];
  }
  return held;
}

}  // namespace

void NeighbourCache::resize(std::size_t source_points, int new_capacity) {
  capacity = new_capacity;
  index.resize(source_points * static_cast<std::size_t>(new_capacity));
  count.resize(source_points);
  query.resize(source_points);
  bound.resize(source_points);
  queried.resize(source_points);
  invalidate();
}

void NeighbourCache::invalidate() {
  for (double& b : bound) b = -1.0;
  last_queries = 0;
}

void associate_cached(const KdTree& target_tree, const PointCloud& target, const PointCloud& source,
                      const Eigen::Isometry3d& T_target_source, double radius, int num_threads,
                      NeighbourCache* cache, AssociationTable* table) {
  const int k = table->k;
  const int capacity = cache->capacity;
  const double radius_sq = radius * radius;
  const double candidate_radius = NeighbourCache::kRadiusMargin * radius;
  const double candidate_radius_sq = candidate_radius * candidate_radius;
  const Eigen::Matrix3d R = T_target_source.linear();
  const Eigen::Vector3d t = T_target_source.translation();
  parallel_for(num_threads, static_cast<std::ptrdiff_t>(source.size()), [&](std::ptrdiff_t jj) {
    const std::size_t j = static_cast<std::size_t>(jj);
    const std::size_t slot = j * static_cast<std::size_t>(k);
    const std::size_t cslot = j * static_cast<std::size_t>(capacity);
    std::uint32_t* out_idx = &table->index[slot];
    double* out_d = &table->dist_sq[slot];
    std::uint32_t* cand = &cache->index[cslot];
    const Eigen::Vector3d p = R * source[j] + t;
    cache->queried[j] = 0;
    if (cache->bound[j] >= 0.0) {
      const double delta = (p - cache->query[j]).norm();
      const int n = rerank(target, p, cand, cache->count[j], k, radius_sq, out_idx, out_d);
      const double kth = n == k ? std::sqrt(out_d[k - 1]) : radius;
      if (kth + delta < cache->bound[j]) {  // the certificate of neighbour_cache.hpp
        table->count[j] = static_cast<std::uint16_t>(n);
        return;
      }
    }
    // Re-query: the K nearest within r_c around p (their distances go to a stack buffer), then
    // the same re-rank as a cache hit, so that the table's distances and tie order never depend
    // on which path a point took.
    double cand_d[NeighbourCache::kMaxCapacity];
    const int found = target_tree.radius_knn(p, capacity, candidate_radius_sq, cand, cand_d);
    cache->count[j] = static_cast<std::uint16_t>(found);
    cache->bound[j] = found == capacity ? std::sqrt(cand_d[capacity - 1]) : candidate_radius;
    cache->query[j] = p;
    cache->queried[j] = 1;
    table->count[j] =
        static_cast<std::uint16_t>(rerank(target, p, cand, found, k, radius_sq, out_idx, out_d));
  });
  table->recount();
  std::size_t queries = 0;
  for (std::uint8_t q : cache->queried) queries += q;
  cache->last_queries = queries;
}

}  // namespace detail
}  // namespace ppcr
