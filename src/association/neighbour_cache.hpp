// neighbour_cache.hpp - exact incremental association: the k nearest target points within the
// radius, re-ranked from a per-point candidate list and re-queried only where that list cannot
// prove the answer.
//
// For source point j the cache holds the K = capacity (k + 1 for a fast mover without a tie,
// below) nearest target points to q_j (the point's position when they were searched) within the
// candidate radius r_c (> r), and a bound B_j such that every target point NOT in the list is at
// least B_j from q_j:
//   B_j = distance of the K-th candidate when K were found, else r_c (the list is every point
//   within r_c).
// At a new position p_j with delta_j = |p_j - q_j|, every uncached point is at least
// B_j - delta_j from p_j (triangle inequality). Re-ranking the candidates by their distance to
// p_j gives the k nearest within r among them; let D_j be the k-th distance, or r when fewer
// than k are within r. If D_j < B_j - delta_j, no uncached point can be among the true k nearest
// within r, so the re-ranked list IS the answer of a fresh radius-limited kNN query, up to exact
// ties: their order, and, where more than k points tie at the k-th distance, which of them are
// kept (the re-rank orders by distance, then index; the tree keeps the ones it visits first).
// Otherwise the point is re-queried (K candidates within r_c around p_j) and re-ranked. Either
// way the table equals a fresh association, up to those ties.
//
// Same set, cheaper (the "set certificate"): after a point is re-ranked at position p' with n
// neighbours of largest distance m, every target point outside the table is at least G from p',
// G = min(the closest candidate left out, B_j - |p' - q_j|). For a move delta' = |p - p'| < rho_j,
//   rho_j = min(r - m, max((G - m) / 2, G - r))  (n = k),   rho_j = min(r - m, G - r)  (n < k),
// every neighbour stays within r, and either no outside point can overtake one (separation) or
// none can enter the radius; so the table's set is unchanged. Its order is refreshed by
// sorting the n held entries by their distances at p (no candidate distances, no top-k
// selection).
// Both certificates give up 1e-9 r + 1e-12 |p|_1 against rounding (D_j < B_j - delta_j - that at
// p; rho_j - that at p', when rho_j is stored; the L1 norm bounds |p| without a square root). The
// table row must be the one this cache's last call wrote: a call with another table, k or radius
// invalidates the cache first; no other code may write the table between two calls.
//
// Fast movers. A list holds while its point moves less than about B_j - D_j, a small part of B_j
// (on a surface, with K = k + 4 and k = 10: B_j / D_j ~ sqrt(14 / 10), so ~0.15 B_j), and early
// outer iterations move the points by more than that (the benchmark sets: nearly every point
// re-queried in iterations 2-4). Such a list costs a query of K and buys nothing. So a point
// re-queried after moving more than kFastMove x B_j since its last query is queried for its
// k + 1 nearest only (its list then holds k + 1, or fewer when that is every point within r_c).
// Ties: the tree keeps, among points tied at its last distance, those it visits first, so a
// query of k + 1 whose k + 1-th is exactly as near as its k-th is repeated for K, and the row is
// the same as a query of K gives in every case (so are the traces). While a point has moved
// more than kFastMove x B_j since its last query it skips its list (whose certificate would need
// kth < (1 - kFastMove) B_j) and is queried for k + 1 again; once it moves slower it tries its
// list, and a failing one is queried for K. kFastMove = 0.5: see its comment below.
//
// Seeded queries. A re-queried point's list (of at least as many candidates as the query wants)
// holds real target points, so the largest of their squared distances at p, b, bounds the
// distance of the query's last neighbour. The query is bounded by min(b (1 + 1e-9), r_c^2) (the
// 1e-9 against the rounding of the tree's cell bounds) instead of r_c^2: it prunes from its first
// leaf and finds the same neighbours in the same order. The tree visits its cells in the same
// order; until it holds `want` points it also skips the cells beyond the bound, which hold none of
// them, and from then on it prunes by its want-th as the unbounded search does. Should it find
// fewer than it wants (rounding beyond that slack), it is repeated without the bound. The cache
// counts both (last_seeded, last_seed_repeats).
// The argument needs only `want` distinct real target points, not the point's own: a point with
// no list of its own that long (every point in the first call; a fast mover's k + 1 list) takes
// the first `want` of the previous point's list. The points are visited in blocks of 64, each in
// order on one thread, so the previous point's list is the one it was left with in this call
// (queried, or kept); in Z-order (spatial_order.hpp) that point is a neighbour and the bound
// tight. Counted apart (last_neighbour_seeded, last_neighbour_seed_repeats).
//
// Cost (measured with K = 18, before the set certificate): a re-ranked point takes ~120 ns against
// ~820 ns for a k-d tree query (ppcr_microbench: BM_AssociateCached, BM_RadiusKnnQuery); late outer
// iterations move points by a small fraction of the neighbour spacing, so almost every point is
// re-ranked (docs/PERFORMANCE.md).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "association/association_table.hpp"
#include "association/kdtree.hpp"
#include "common/buffer.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;  // parallel.hpp

struct NeighbourCache {
  /// Candidates per source point, K >= k (largest supported: kMaxCapacity).
  int capacity = 0;
  Buffer<std::uint32_t> index;       // capacity slots per source point
  std::vector<std::uint16_t> count;  // candidates held (<= capacity)
  Buffer<double> bound;              // B_j, cloud units; < 0 = no list yet
  Buffer<double> set_radius_sq;      // rho_j^2, squared cloud units; < 0 = none (rho_j <= 0)
  // q_j and p' (where point j was last re-ranked), the tree's frame, are not stored: each is the
  // pose of one of the last kPoses calls applied to the source point, recomputed as that call
  // computed it, to the bit. A list or certificate from an older call is not used (the point is
  // queried again: the same row, as every path gives).
  Buffer<std::uint32_t> query_call;   // the call whose pose gives q_j
  Buffer<std::uint32_t> ranked_call;  // the call whose pose gives p'
  struct Pose {
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
  };
  static constexpr std::uint32_t kPoses = 256;
  std::array<Pose, kPoses> poses;  // call c's pose at poses[c % kPoses]
  std::uint32_t calls = 0;         // associate_cached calls so far
  // The path each point took in the last associate_cached.
  enum Path : std::uint8_t { kReranked = 0, kQueried = 1, kResorted = 2 };
  std::vector<std::uint8_t> path;
  // How a queried point's query was bounded in the last associate_cached ("Seeded queries"):
  // by r_c^2 only, by its list's seed, or by the seed and then again without it.
  // kNeighbourSeeded*: bounded by the previous point's list instead (no list of its own to seed
  // from).
  enum Seed : std::uint8_t {
    kUnseeded = 0,
    kSeeded = 1,
    kSeedRepeated = 2,
    kNeighbourSeeded = 3,
    kNeighbourSeedRepeated = 4
  };
  std::vector<std::uint8_t> seed;  // meaningful where path is kQueried
  // Counts of points, not of tree calls: a point queried twice counts once.
  std::size_t last_queries = 0;  // points the last associate_cached queried the k-d tree for
  std::size_t last_seeded = 0;   // of those, points whose first query was bounded by their own list
  // Of those, points whose seeded query found fewer than it wanted and was repeated without the
  // seed. (A fast mover's re-query for capacity after a tie at its k-th is not this repeat,
  // and is not counted.)
  std::size_t last_seed_repeats = 0;
  // Of the points queried, those whose first query was bounded by the previous point's list, and
  // of those, the ones repeated without that seed.
  std::size_t last_neighbour_seeded = 0;
  std::size_t last_neighbour_seed_repeats = 0;
  std::size_t last_resorted = 0;  // rows it refreshed by the set certificate
  // What the last call was for: another table, k or radius invalidates the cache first.
  const AssociationTable* table = nullptr;
  int table_k = 0;
  double table_radius = 0.0;

  static constexpr int kMaxCapacity = 256;
  /// r_c = kRadiusMargin * r: a point near the edge of the data keeps its (incomplete) list
  /// until it has moved (kRadiusMargin - 1) * r.
  static constexpr double kRadiusMargin = 1.25;
  /// A point re-queried after moving more than kFastMove * B_j since its last query is queried
  /// for k + 1 candidates, not capacity (see the comment at the top). 0.5 was the best of 0.3-1.0
  /// on the bunny set; 0.4 and 0.7 are within the timing noise of it (docs/PERFORMANCE.md).
  static constexpr double kFastMove = 0.5;

  /// Sizes the cache for source_points points and capacity candidates each, and empties it. The
  /// per-point marks are written on the threads of `parallel` (null: the calling thread): a new
  /// buffer's first touch is a page fault (buffer.hpp).
  void resize(std::size_t source_points, int capacity, const Parallel* parallel = nullptr);
  /// Reserves room for source_points points of capacity candidates (no write, no reset), so that
  /// resizing up to that later allocates nothing.
  void reserve(std::size_t source_points, int capacity);
  /// Forgets every list (the next associate_cached queries every point); on the threads of
  /// `parallel`.
  void invalidate(const Parallel* parallel = nullptr);
};

/// As associate() (association_table.hpp), with the cache: same table, fewer k-d tree queries. The
/// cache must be sized for source.size() points with capacity >= table->k, and be invalidated
/// when the tree, the target or the source changes (a new table, k or radius invalidates it
/// itself). radius > 0 (asserted). Allocation-free. The result does not depend on the thread
/// count.
void associate_cached(const KdTree& target_tree, const PointCloud& target, const PointCloud& source,
                      const Eigen::Isometry3d& T_target_source, double radius,
                      const Parallel* parallel, NeighbourCache* cache, AssociationTable* table);

/// Spreads a coarse level's lists over the full source, in place (RegistrationOptions::
/// coarse_stride): the cache and table hold one row per point of the coarse level, whose point i
/// is point i * stride of the full source (stride >= 2); afterwards they hold `points` rows, row i
/// * stride being the old row i (candidates, bounds, certificates, and the table row they certify)
/// and every other point without a list. The certificates speak of a source point's positions and
/// the tree, not of the cloud that holds the point, so the next associate_cached with the full
/// source (same tree, target, k and radius) fills the table a fresh association would, querying
/// only where the lists cannot prove the answer (a list-less point's query is bounded by its
/// previous point's list when that list is long enough, "Seeded queries"). The rows grow within the
/// vectors' capacity: allocation-free when the cache had room reserved for `points` (reserve()) and
/// the table was sized for them, before both were sized for the coarse level. The cache must hold
/// its last call's lists for `table`. On the threads of `parallel` (null: the calling thread); the
/// result does not depend on their number.
void spread_lists(std::size_t stride, std::size_t points, NeighbourCache* cache,
                  AssociationTable* table, const Parallel* parallel = nullptr);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
