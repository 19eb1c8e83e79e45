// neighbour_cache.cpp - see neighbour_cache.hpp for the certificate.
#include "association/neighbour_cache.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "common/parallel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// Squared distances of targets idx[0..n) to p, by the k-d tree's own expression (kdtree.hpp):
// a query's candidates come with the tree's distances, a cache hit's are computed here, alike
// (see squared_distance), so the rows' order, ties included, does not depend on the path.
void distances(const PointCloud& target, const Eigen::Vector3d& p, const std::uint32_t* idx, int n,
               double* d) {
  for (int c = 0; c < n; ++c) d[c] = squared_distance(p.data(), target[idx[c]].data());
}

// Inserts (dist, id) into the sorted prefix [0, i) of out_idx/out_d by (distance, index), shifting
// larger entries up from slot i: the one order of every path below.
void insert_sorted(int i, double dist, std::uint32_t id, std::uint32_t* out_idx, double* out_d) {
  while (i > 0 && (out_d[i - 1] > dist || (out_d[i - 1] == dist && out_idx[i - 1] > id))) {
    out_d[i] = out_d[i - 1];
    out_idx[i] = out_idx[i - 1];
    --i;
  }
  out_d[i] = dist;
  out_idx[i] = id;
}

// Re-ranks candidates idx[0..n), at squared distances dist[0..n) from p, into the table slots
// out_idx/out_d (ascending; ties by target index), keeping at most k within radius_sq. Returns
// the count. *left_out_sq is set to the smallest squared distance of a candidate not kept (+inf
// if none).
int rerank(const std::uint32_t* idx, const double* dist, int n, int k, double radius_sq,
           std::uint32_t* out_idx, double* out_d, double* left_out_sq) {
  int held = 0;
  double left_out = std::numeric_limits<double>::infinity();
  for (int c = 0; c < n; ++c) {
    const double d = dist[c];
    if (!(d <= radius_sq)) {
      left_out = d < left_out ? d : left_out;
      continue;
    }
    if (held == k && !(d < out_d[k - 1] || (d == out_d[k - 1] && idx[c] < out_idx[k - 1]))) {
      left_out = d < left_out ? d : left_out;
      continue;
    }
    if (held == k) left_out = out_d[k - 1] < left_out ? out_d[k - 1] : left_out;  // evicted
    insert_sorted(held < k ? held++ : k - 1, d, idx[c], out_idx, out_d);
  }
  *left_out_sq = left_out;
  return held;
}

// Refreshes a row whose set is certified: distances at p, then an insertion sort by (distance,
// index), the order rerank produces.
void resort(const PointCloud& target, const Eigen::Vector3d& p, int n, std::uint32_t* idx,
            double* d) {
  distances(target, p, idx, n, d);
  for (int m = 1; m < n; ++m) insert_sorted(m, d[m], idx[m], idx, d);
}

// rho_j^2 of the set certificate (neighbour_cache.hpp) after a re-rank with n of k held, m the
// largest held distance (0 if none), every outside point at least outside_min away, and `margin`
// given up against rounding; -1 (none) when rho_j <= 0.
double set_radius_sq(int n, int k, double m, double radius, double outside_min, double margin) {
  const double enter = outside_min - radius;  // no outside point enters the radius
  const double rho = (n == k ? std::min(radius - m, std::max(0.5 * (outside_min - m), enter))
                             : std::min(radius - m, enter)) -
                     margin;
  return rho > 0.0 ? rho * rho : -1.0;
}

// op(array, length) for each per-point array of the cache, with its length for `points` points of
// `capacity` candidates: every array that resize, reserve and spread_lists size, in one list.
template <class Op>
void for_each_array(NeighbourCache* cache, std::size_t points, std::size_t capacity, Op op) {
  op(cache->index, points * capacity);
  op(cache->count, points);
  op(cache->query_call, points);
  op(cache->bound, points);
  op(cache->path, points);
  op(cache->seed, points);
  op(cache->ranked_call, points);
  op(cache->set_radius_sq, points);
}

}  // namespace

void NeighbourCache::resize(std::size_t source_points, int new_capacity, const Parallel* parallel) {
  capacity = new_capacity;
  for_each_array(this, source_points, static_cast<std::size_t>(new_capacity),
                 [](auto& array, std::size_t length) { array.resize(length); });
  invalidate(parallel);
}

void NeighbourCache::reserve(std::size_t source_points, int reserved_capacity) {
  for_each_array(this, source_points, static_cast<std::size_t>(reserved_capacity),
                 [](auto& array, std::size_t length) { array.reserve(length); });
}

void NeighbourCache::invalidate(const Parallel* parallel) {
  constexpr std::size_t kBlock = 4096;
  const std::size_t n = bound.size();
  assert(set_radius_sq.size() == n);
  parallel_for_blocks(parallel, n, kBlock, [&](std::ptrdiff_t, std::size_t begin, std::size_t end) {
    std::fill(bound.data() + begin, bound.data() + end, -1.0);
    std::fill(set_radius_sq.data() + begin, set_radius_sq.data() + end, -1.0);
  });
  table = nullptr;
  last_queries = 0;
  last_seeded = 0;
  last_seed_repeats = 0;
  last_neighbour_seeded = 0;
  last_neighbour_seed_repeats = 0;
  last_resorted = 0;
}

namespace {

// What one associate_cached call shares between its points.
struct CallContext {
  const KdTree& tree;
  const PointCloud& target;
  const PointCloud& source;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  std::uint32_t call;  // this call's number (NeighbourCache::calls)
  int k, capacity;
  double radius, radius_sq, candidate_radius, candidate_radius_sq;
  NeighbourCache* cache;
  AssociationTable* table;
};

// Per point: its position, its rows, and the candidates' squared distances at p.
struct PointState {
  std::size_t j = 0;
  Eigen::Vector3d p;
  std::uint32_t* out_idx = nullptr;            // the table's row
  double out_d[NeighbourCache::kMaxCapacity];  // its squared distances at p (not kept)
  std::uint32_t* cand = nullptr;
  double margin = 0.0;  // what both certificates give up against rounding at p
  double left_out_sq = 0.0;
  bool listed_distances = false;                // cand_d holds the list's distances at p
  double cand_d[NeighbourCache::kMaxCapacity];  // the candidates' squared distances to p
  std::uint8_t seed = NeighbourCache::kUnseeded;
};

// Where source point j was at call `call`, computed as that call computed p (associate_point), or
// false when that call's pose is no longer kept.
bool position_at(const CallContext& c, std::uint32_t call, std::size_t j, Eigen::Vector3d* p) {
  if (c.call - call >= NeighbourCache::kPoses) return false;
  const NeighbourCache::Pose& pose = c.cache->poses[call % NeighbourCache::kPoses];
  *p = pose.R * c.source[j] + pose.t;
  return true;
}

// The row re-ranked at p: its count, p' (this call) and rho^2 (outside_min bounds every point not
// kept).
void set_ranked(const CallContext& c, const PointState& s, int n, double m, double outside_min) {
  c.table->count[s.j] = static_cast<std::uint16_t>(n);
  c.cache->ranked_call[s.j] = c.call;
  c.cache->set_radius_sq[s.j] = set_radius_sq(n, c.k, m, c.radius, outside_min, s.margin);
}

// The list certificate of neighbour_cache.hpp for a point that moved delta since its list's
// query: true when the re-ranked candidates are the row. It needs kth + delta < B_j, so a fast
// mover (delta > kFastMove x B_j) goes straight to the query (the same table): its list would
// pass only if kth < (1 - kFastMove) B_j, far below the k-th of K candidates on a surface
// (~0.85 B_j), and a point that moved B_j or more cannot pass at all.
bool certified_rerank(const CallContext& c, PointState* s, double delta) {
  NeighbourCache& cache = *c.cache;
  const std::size_t j = s->j;
  if (!(delta <= NeighbourCache::kFastMove * cache.bound[j])) return false;
  // Distances first (independent gathers the CPU overlaps), then the branchy selection.
  distances(c.target, s->p, s->cand, cache.count[j], s->cand_d);
  s->listed_distances = true;
  const int n = rerank(s->cand, s->cand_d, cache.count[j], c.k, c.radius_sq, s->out_idx, s->out_d,
                       &s->left_out_sq);
  const double m = n > 0 ? std::sqrt(s->out_d[n - 1]) : 0.0;
  const double kth = n == c.k ? m : c.radius;
  if (!(kth + delta < cache.bound[j] - s->margin)) return false;
  set_ranked(c, *s, n, m, std::min(std::sqrt(s->left_out_sq), cache.bound[j] - delta));
  cache.path[j] = NeighbourCache::kReranked;
  return true;
}

// The want nearest within r_c around p into cand / cand_d. A point with a list of at least
// `want` candidates seeds its query, else one whose block's previous point has such a list takes
// that (neighbour_cache.hpp, "Seeded queries", for why the seeded search finds the same want
// nearest in the same order). prev: that point, or -1.
int seeded_query(const CallContext& c, PointState* s, int want, std::ptrdiff_t prev) {
  const NeighbourCache& cache = *c.cache;
  double seed_sq = std::numeric_limits<double>::infinity();  // none: bounded by r_c^2 only
  bool own = false;  // seeded by the point's own list, else by the previous point's
  const int listed = cache.bound[s->j] >= 0.0 ? cache.count[s->j] : 0;
  if (listed >= want) {
    if (!s->listed_distances) distances(c.target, s->p, s->cand, listed, s->cand_d);
    double b = 0.0;
    for (int i = 0; i < listed; ++i) b = s->cand_d[i] > b ? s->cand_d[i] : b;
    seed_sq = seed_bound_sq(b);
    own = true;
  } else if (prev >= 0 && cache.count[static_cast<std::size_t>(prev)] >= want) {
    // prev was visited before j in this call, so its list is valid (queried, or kept).
    assert(cache.bound[static_cast<std::size_t>(prev)] >= 0.0);
    // `want` real target points (the first of the previous point's list) bound the distance
    // of this point's want-th neighbour as well as its own list would.
    const std::uint32_t* theirs =
        &cache.index[static_cast<std::size_t>(prev) * static_cast<std::size_t>(c.capacity)];
    seed_sq = seed_bound_sq(s->p, c.target, theirs, want);
  }
  const SeededKnn knn =
      seeded_radius_knn(c.tree, s->p, want, seed_sq, c.candidate_radius_sq, s->cand, s->cand_d);
  if (knn.outcome != SeedOutcome::kUnseeded) {
    const bool repeated = knn.outcome == SeedOutcome::kRepeated;
    if (own) {
      s->seed = repeated ? NeighbourCache::kSeedRepeated : NeighbourCache::kSeeded;
    } else {
      s->seed =
          repeated ? NeighbourCache::kNeighbourSeedRepeated : NeighbourCache::kNeighbourSeeded;
    }
  }
  return knn.found;
}

// Re-query: the K nearest within r_c around p, then the same re-rank as a cache hit, so that the
// table's tie order never depends on which path a point took. The tree's distances are computed
// as distances() computes them. A fast mover is queried for k + 1 only; the k + 1-th decides
// ties (neighbour_cache.hpp, "Fast movers"): when it is as near as the k-th, the point is
// queried for capacity after all.
void requery(const CallContext& c, PointState* s, bool fast, std::ptrdiff_t prev) {
  NeighbourCache& cache = *c.cache;
  const std::size_t j = s->j;
  int want = fast ? std::min(c.k + 1, c.capacity) : c.capacity;
  int found = seeded_query(c, s, want, prev);
  if (want < c.capacity && found == want && !(s->cand_d[c.k] > s->cand_d[c.k - 1])) {
    want = c.capacity;
    found = c.tree.radius_knn(s->p, want, c.candidate_radius_sq, s->cand, s->cand_d);
  }
  cache.count[j] = static_cast<std::uint16_t>(found);
  cache.bound[j] = found == want ? std::sqrt(s->cand_d[want - 1]) : c.candidate_radius;
  cache.query_call[j] = c.call;
  cache.path[j] = NeighbourCache::kQueried;
  cache.seed[j] = s->seed;
  const int n =
      rerank(s->cand, s->cand_d, found, c.k, c.radius_sq, s->out_idx, s->out_d, &s->left_out_sq);
  set_ranked(c, *s, n, n > 0 ? std::sqrt(s->out_d[n - 1]) : 0.0,
             std::min(std::sqrt(s->left_out_sq), cache.bound[j]));
}

// Point j: the set certificate (re-sort the row), else the list certificate (re-rank the
// candidates), else a query.
void associate_point(const CallContext& c, std::size_t j, std::ptrdiff_t prev) {
  NeighbourCache& cache = *c.cache;
  const std::size_t slot = j * static_cast<std::size_t>(c.k);
  PointState s;  // cand_d left uninitialised: written before it is read
  s.j = j;
  s.p = c.R * c.source[j] + c.t;
  s.out_idx = &c.table->index[slot];
  s.cand = &cache.index[j * static_cast<std::size_t>(c.capacity)];
  // The set certificate, |p - p'| < rho_j, compared squared (rho_j > 0 is stored squared; the
  // margin subtracted from rho_j when it was stored covers the rounding of either side).
  Eigen::Vector3d then;
  const bool listed = cache.bound[j] >= 0.0;
  const bool ranked_kept = listed && position_at(c, cache.ranked_call[j], j, &then);
  if (ranked_kept && (s.p - then).squaredNorm() < cache.set_radius_sq[j]) {
    resort(c.target, s.p, c.table->count[j], s.out_idx, s.out_d);
    cache.path[j] = NeighbourCache::kResorted;
    return;
  }
  // 1e-9 of the radius, and 1e-12 of |p| for coordinates far larger than the radius, bounded by
  // the L1 norm (no square root). (Without it, an exact tie such as sqrt(18) + sqrt(2) =
  // sqrt(32) can compute as strictly less.)
  s.margin = 1e-9 * c.radius + 1e-12 * s.p.cwiseAbs().sum();
  // A point that moved more than kFastMove x B_j since its last query is likely to move past a
  // new list's margin too: it is queried for its k + 1 nearest only (a cheaper query).
  // q_j is p' when the point was re-ranked by the call that queried it (requery ranks what it
  // finds): then already holds it.
  bool fast = false;
  if (listed && ((ranked_kept && cache.query_call[j] == cache.ranked_call[j]) ||
                 position_at(c, cache.query_call[j], j, &then))) {
    const double delta = (s.p - then).norm();
    fast = delta > NeighbourCache::kFastMove * cache.bound[j];
    if (certified_rerank(c, &s, delta)) return;
  }
  requery(c, &s, fast, prev);
}

// The last call's path and seed counts (NeighbourCache::last_*).
void count_paths(NeighbourCache* cache) {
  std::size_t queries = 0, seeded = 0, repeats = 0, resorted = 0;
  std::size_t neighbour_seeded = 0, neighbour_repeats = 0;
  for (std::size_t j = 0; j < cache->path.size(); ++j) {
    const bool queried = cache->path[j] == NeighbourCache::kQueried;
    const std::uint8_t s = cache->seed[j];
    queries += queried;
    seeded += queried && (s == NeighbourCache::kSeeded || s == NeighbourCache::kSeedRepeated);
    repeats += queried && s == NeighbourCache::kSeedRepeated;
    neighbour_seeded += queried && (s == NeighbourCache::kNeighbourSeeded ||
                                    s == NeighbourCache::kNeighbourSeedRepeated);
    neighbour_repeats += queried && s == NeighbourCache::kNeighbourSeedRepeated;
    resorted += cache->path[j] == NeighbourCache::kResorted;
  }
  cache->last_queries = queries;
  cache->last_seeded = seeded;
  cache->last_seed_repeats = repeats;
  cache->last_neighbour_seeded = neighbour_seeded;
  cache->last_neighbour_seed_repeats = neighbour_repeats;
  cache->last_resorted = resorted;
}

}  // namespace

void associate_cached(const KdTree& target_tree, const PointCloud& target, const PointCloud& source,
                      const Eigen::Isometry3d& T_target_source, double radius,
                      const Parallel* parallel, NeighbourCache* cache, AssociationTable* table) {
  // radius > 0 (checked by validate()): the certificates rely on kth >= 0 and r - m >= 0.
  assert(radius > 0.0);
  assert(table->k <= cache->capacity && cache->capacity <= NeighbourCache::kMaxCapacity);
  const double candidate_radius = NeighbourCache::kRadiusMargin * radius;
  const std::uint32_t call = cache->calls++;
  cache->poses[call % NeighbourCache::kPoses] = {T_target_source.linear(),
                                                 T_target_source.translation()};
  const CallContext c{target_tree,
                      target,
                      source,
                      T_target_source.linear(),
                      T_target_source.translation(),
                      call,
                      table->k,
                      cache->capacity,
                      radius,
                      radius * radius,
                      candidate_radius,
                      candidate_radius * candidate_radius,
                      cache,
                      table};
  // The lists and rho hold for the table, k and radius of the last call (the set certificate
  // re-sorts that table's rows in place): anything else starts afresh.
  if (cache->table != table || cache->table_k != c.k || cache->table_radius != radius) {
    cache->invalidate(parallel);
  }
  // Points in blocks of kSeedBlock, each visited in order by one thread: a point without a list
  // to seed its query from may seed it from the block's previous point's list ("Seeded
  // queries").
  constexpr std::size_t kSeedBlock = 64;
  parallel_for_blocks(
      parallel, source.size(), kSeedBlock, [&](std::ptrdiff_t, std::size_t begin, std::size_t end) {
        for (std::size_t j = begin; j < end; ++j) {
          associate_point(c, j, j > begin ? static_cast<std::ptrdiff_t>(j - 1) : -1);
        }
      });
  cache->table = table;
  cache->table_k = c.k;
  cache->table_radius = radius;
  table->recount();
  count_paths(cache);
}

void spread_lists(std::size_t stride, std::size_t points, NeighbourCache* cache,
                  AssociationTable* table, const Parallel* parallel) {
  const std::size_t coarse = cache->count.size();
  assert(cache->table == table && table->count.size() == coarse && stride >= 2 &&
         (coarse == 0 || (coarse - 1) * stride < points));
  const std::size_t capacity = static_cast<std::size_t>(cache->capacity);
  const std::size_t k = static_cast<std::size_t>(table->k);
  // Grow (vector::resize keeps the rows held), then move row i to i * stride (below).
  for_each_array(cache, points, capacity,
                 [](auto& array, std::size_t length) { array.resize(length); });
  table->resize(points, table->k);
  auto move_row = [&](std::size_t i) {
    const std::size_t j = i * stride;
    std::copy_n(&cache->index[i * capacity], capacity, &cache->index[j * capacity]);
    cache->count[j] = cache->count[i];
    cache->query_call[j] = cache->query_call[i];
    cache->bound[j] = cache->bound[i];
    cache->ranked_call[j] = cache->ranked_call[i];
    cache->set_radius_sq[j] = cache->set_radius_sq[i];
    std::copy_n(&table->index[i * k], k, &table->index[j * k]);
    table->count[j] = table->count[i];
  };
  // Rows [lo, hi) with lo = ceil(hi / stride) move at once, on the threads of `parallel`: their
  // destinations, from lo * stride >= hi on, hold no row still to move (those are below lo) and
  // none of this round's (below hi). Then the rows below lo, until row 0, which stays. Each row
  // is read before any row is written over it (its writer, row m / stride, lies in a later
  // round), so every destination receives its source's original row.
  constexpr std::size_t kBlock = 1024;
  for (std::size_t hi = coarse; hi > 1;) {
    const std::size_t lo = std::max<std::size_t>(1, (hi + stride - 1) / stride);
    parallel_for_blocks(parallel, hi - lo, kBlock,
                        [&](std::ptrdiff_t, std::size_t begin, std::size_t end) {
                          for (std::size_t i = lo + begin; i < lo + end; ++i) move_row(i);
                        });
    hi = lo;
  }
  parallel_for_blocks(parallel, points, kBlock,
                      [&](std::ptrdiff_t, std::size_t begin, std::size_t end) {
                        for (std::size_t j = begin; j < end; ++j) {
                          // No list: queried by the next call (j / stride < coarse otherwise).
                          if (j % stride != 0) {
                            cache->bound[j] = -1.0;
                            cache->set_radius_sq[j] = -1.0;
                          }
                        }
                      });
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
