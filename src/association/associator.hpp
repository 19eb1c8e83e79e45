// associator.hpp - the association step of the outer loop (paper Sec. 3.1): for each source
// point moved by the current pose, up to k target points within the radius.
//
// Behind this one interface live two speed measures, each exact (the table equals a fresh k-d
// tree query of every point; tests/core/test_associator.cpp checks both against the plain path):
//  - a neighbour cache (neighbour_cache.hpp): candidate lists that prove most points' answers
//    without a query;
//  - a coarse level: while the caller asks for it (the registration does while the EM scale
//    settles: coarse, then halving), only every stride-th source point (in Z-order, so spread over
//    the whole cloud) is associated; the first association of every point spreads the coarse
//    level's lists over every point.
// With the plane model and source normals it also records what each pair's normal is formed from
// (the rows' source normals and the association's rotation: PairNormalSource, pair_normals.hpp).
// When asked, it leaves out the rows whose nearest target point lies on the target's boundary
// (boundary.hpp; AssociationTable::left_out).
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "association/association_table.hpp"
#include "association/kdtree.hpp"
#include "association/neighbour_cache.hpp"
#include "model/normal_equations.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/options.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;  // parallel.hpp

class Associator {
 public:
  struct Settings {
    int k = RegistrationOptions{}.max_neighbours;  // neighbours per source point
    double radius = 1.0;                           // cloud units
    int cache_extra = 0;                 // extra cached candidates per point (0 = no cache)
    std::size_t coarse_stride = 1;       // 1 = no coarse level
    const Parallel* parallel = nullptr;  // null: the calling thread alone
  };

  /// The target side, kept by pointer until the next call. boundary: one flag per target point
  /// (compute_normals, pca_normals.hpp), or null: no row is ever left out.
  void set_target(const KdTree* tree, const PointCloud* target,
                  const std::uint8_t* boundary = nullptr);

  /// Set-up for one source (allocates; reuses buffers of an equal-size source). source_normals:
  /// one per source point, or null for no pair normals.
  void prepare(const Settings& settings, const PointCloud& source,
               const std::vector<Eigen::Vector3d>* source_normals);

  /// Associates at T (internal frame): the coarse level while `coarse` and it exists, else every
  /// point. A coarse level that finds no pair is dropped (its points may miss a small overlap that
  /// others reach) and every point is associated instead; once every point has been associated,
  /// the coarse level is gone for the rest of the run, whatever `coarse` asks.
  /// With leave_out_boundary, then leave_out_boundary_rows(). Allocation-free.
  void find(bool coarse, const Eigen::Isometry3d& T, bool leave_out_boundary = false);
  /// find() at *T_start; when that finds no pair and *T_start is not T, find() at T, with
  /// *T_start set to T (a start extrapolated beyond every target point falls back to the last
  /// solved pose). Returns whether it fell back. Allocation-free.
  bool find_from(bool coarse, const Eigen::Isometry3d& T, Eigen::Isometry3d* T_start,
                 bool leave_out_boundary = false);

  bool has_coarse_level() const { return use_coarse_; }
  /// The table holds the coarse level's rows.
  bool coarse() const { return coarse_associated_; }
  /// The source points the table's rows refer to.
  const PointCloud& points() const { return coarse_associated_ ? coarse_points_ : *source_; }
  const AssociationTable& table() const { return table_; }
  /// The source normals of the table's rows and the rotation of the last association, from which
  /// the plane pass forms the pairs' normals; null without source normals. The pointer stays
  /// valid, its contents follow each find().
  const PairNormalSource* pair_normal_source() const {
    return source_normals_ != nullptr ? &pair_source_ : nullptr;
  }

 private:
  void associate(bool coarse, const Eigen::Isometry3d& T);
  // Leaves out the rows whose nearest target point lies on the target's boundary, unless that
  // would leave out more than half of the matched rows: a target made mostly of boundary points
  // (a strip, a sparse cloud) has no interior to prefer, and its pairs are all there is.
  void leave_out_boundary_rows();

  const KdTree* tree_ = nullptr;
  const PointCloud* target_ = nullptr;
  const std::uint8_t* boundary_ = nullptr;
  const PointCloud* source_ = nullptr;
  const std::vector<Eigen::Vector3d>* source_normals_ = nullptr;
  Settings settings_;
  bool use_cache_ = false;
  bool use_coarse_ = false;
  bool coarse_associated_ = false;
  // The coarse level: every stride-th source point and its normal. It uses the first rows of the
  // table and the cache, which grow within their capacity at the switch (spread_lists).
  PointCloud coarse_points_;
  std::vector<Eigen::Vector3d> coarse_normals_;
  AssociationTable table_;
  NeighbourCache cache_;
  PairNormalSource pair_source_;
};

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
