// registration.cpp - the outer loop (paper Sec. 3.2): associate, solve, compose, ask the
// termination monitor. Nothing else lives here.
//
// Internal frame: both clouds are shifted by their per-axis medians (o_t for the target, o_s for
// the source), so that coordinates are small even for georeferenced clouds and the
// left-perturbation twist acts about the middle of the target's data (a median, unlike a mean,
// is not dragged away by a few absurd points). A pose T in that frame maps to
//   T_target_source = Tr(o_t) * T * Tr(-o_s).
#include "ppcr/registration.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "association.hpp"
#include "kdtree.hpp"
#include "lm_solver.hpp"
#include "neighbour_cache.hpp"
#include "pair_normals.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/voxel.hpp"
#include "scale_schedule.hpp"
#include "spatial_order.hpp"
#include "target_normals.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace {

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

Status invalid(const std::string& what) { return Status(StatusCode::kInvalidArgument, what); }

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

// Drops non-finite points; optionally voxel-filters. Returns the number dropped in *dropped.
Status prepare_cloud(const PointCloud& in, double voxel, const char* name, PointCloud* out,
                     std::size_t* dropped) {
  out->clear();
  out->reserve(in.size());
  for (const Eigen::Vector3d& p : in) {
    if (p.allFinite()) out->push_back(p);
  }
  *dropped = in.size() - out->size();
  if (voxel > 0.0 && !out->empty()) {
    PointCloud filtered;
    Status s = voxel_downsample(*out, voxel, &filtered);
    if (!s.ok()) return Status(s.code(), std::string(name) + ": " + s.message());
    *out = std::move(filtered);
  }
  if (out->size() < 3) {
    return Status(StatusCode::kEmptyCloud,
                  std::string(name) + " has " + std::to_string(out->size()) +
                      " usable point(s) (of " + std::to_string(in.size()) + ", " +
                      std::to_string(*dropped) + " non-finite" +
                      (voxel > 0.0 ? ", after a voxel filter of " + num(voxel) : std::string()) +
                      "); at least 3 are needed");
  }
  return Status::Ok();
}

// Per-axis median of the cloud: the origin of the internal frame. Unlike the mean, a few absurd
// but finite points (a lidar's garbage return at 1e9 m) cannot drag it away from the data, which
// would couple rotation and translation in the twist and stall the LM. O(n) (nth_element).
Eigen::Vector3d median_origin(const PointCloud& cloud, std::vector<double>* scratch) {
  Eigen::Vector3d origin;
  scratch->resize(cloud.size());
  const auto mid = scratch->begin() + static_cast<std::ptrdiff_t>(cloud.size() / 2);
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t i = 0; i < cloud.size(); ++i) (*scratch)[i] = cloud[i][axis];
    std::nth_element(scratch->begin(), mid, scratch->end());
    origin[axis] = *mid;
  }
  return origin;
}

// Shifts `cloud` by its median origin into *centered, dropping (in both, counted in *dropped)
// points whose squared distance from the origin overflows: no squared distance to them is
// finite, so they can take no part in association or in the cost. Fails below 3 points.
// Refuses clouds so far from the coordinate origin that a double cannot resolve a thousandth of
// their own extent there (a 2 m scene 1e14 m from the origin: steps of 2 cm). A cloud whose
// points all round to one value is accepted: it is a cloud of identical points.
Status center_cloud(const char* name, std::size_t input_size, PointCloud* cloud,
                    PointCloud* centered, Eigen::Vector3d* origin, std::size_t* dropped,
                    std::vector<double>* scratch) {
  *origin = median_origin(*cloud, scratch);
  centered->resize(cloud->size());
  std::size_t kept = 0;
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const Eigen::Vector3d c = (*cloud)[i] - *origin;
    if (!std::isfinite(c.squaredNorm())) continue;
    (*cloud)[kept] = (*cloud)[i];
    (*centered)[kept] = c;
    ++kept;
  }
  *dropped += cloud->size() - kept;
  cloud->resize(kept);
  centered->resize(kept);
  double extent = 0.0;
  for (const Eigen::Vector3d& c : *centered) extent = std::max(extent, c.cwiseAbs().maxCoeff());
  const double distance = origin->cwiseAbs().maxCoeff();
  const double resolution = distance * std::numeric_limits<double>::epsilon();
  if (extent > 0.0 && resolution > 1e-3 * extent) {
    return Status(StatusCode::kInvalidArgument,
                  std::string(name) + " lies ~" + num(distance) +
                      " from the coordinate origin, where doubles resolve only " + num(resolution) +
                      ", more than a thousandth of its extent " + num(extent) +
                      ": shift both clouds nearer the origin");
  }
  if (kept < 3) {
    return Status(StatusCode::kEmptyCloud,
                  std::string(name) + " has " + std::to_string(kept) + " usable point(s) (of " +
                      std::to_string(input_size) + ", " + std::to_string(*dropped) +
                      " non-finite or too far from the others for a finite squared distance); "
                      "at least 3 are needed");
  }
  return Status::Ok();
}

std::string extent(const PointCloud& cloud, const Eigen::Isometry3d& T) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
  for (const Eigen::Vector3d& p : cloud) {
    const Eigen::Vector3d q = T * p;
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  return "[" + num(lo.x()) + ", " + num(hi.x()) + "] x [" + num(lo.y()) + ", " + num(hi.y()) +
         "] x [" + num(lo.z()) + ", " + num(hi.z()) + "]";
}

Eigen::Isometry3d translation(const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = t;
  return T;
}

// The inner LM's function_tolerance in the EM scale's fine phase (lm.hpp), or 0 for none (no EM
// scale, or function_tolerance throughout). kAutomatic: with the plane model and the cost-drop
// criterion alone (the defaults), 1e-2 capped at the cost-drop threshold (a solve that ends on
// its one step, taken unevaluated, reads as a drop of 0: with the cap it counts as low only if
// that step was predicted to lower the cost by less than the threshold, and the motion guard,
// if on, finds the source settled; after evaluated steps the drop is theirs), and never
// stricter than function_tolerance; otherwise none. The other criteria read what one-step
// solves change: mse-prev the motion per outer iteration, successful-steps the steps per solve.
double fine_phase_tolerance(const RegistrationOptions& o) {
  if (o.weights.scale_mode != ScaleMode::kEM) return 0.0;
  if (o.lm.fine_function_tolerance != LMOptions::kAutomatic) return o.lm.fine_function_tolerance;
  if (o.error_model != ErrorModel::kPlane || o.termination.criteria != kCriterionCostDrop) {
    return 0.0;
  }
  const double loosened =
      std::min(LMOptions::kPlaneFineTolerance, o.termination.cost_drop_threshold);
  return loosened > o.lm.function_tolerance ? loosened : 0.0;
}

// The coarse level's stride (RegistrationOptions::coarse_stride) for a source of n points, 1 for
// none: only with the EM scale; kAutomatic is kPlaneCoarseStride with the plane model and 1 with
// the point model; lowered to n / kMinCoarsePoints where that is smaller.
std::size_t coarse_stride(const RegistrationOptions& o, std::size_t n) {
  if (o.weights.scale_mode != ScaleMode::kEM) return 1;
  int stride = o.coarse_stride;
  if (stride == RegistrationOptions::kAutomatic) {
    stride = o.error_model == ErrorModel::kPlane ? RegistrationOptions::kPlaneCoarseStride : 1;
  }
  return std::max<std::size_t>(
      1, std::min(static_cast<std::size_t>(stride), n / RegistrationOptions::kMinCoarsePoints));
}

}  // namespace

Status validate(const RegistrationOptions& o) {
  if (!finite_positive(o.radius)) return invalid("radius must be > 0, got " + num(o.radius));
  if (o.max_neighbours < 1 || o.max_neighbours > detail::AssociationTable::kMaxNeighbours) {
    return invalid("max_neighbours must be in [1, 1024], got " + std::to_string(o.max_neighbours));
  }
  const WeightOptions& w = o.weights;
  if (w.model == WeightModel::kStudentT && !finite_positive(w.dof)) {
    return invalid("dof must be > 0, got " + num(w.dof));
  }
  if (w.scale_mode == ScaleMode::kFixed && !finite_positive(w.scale)) {
    return invalid("a fixed scale must be > 0, got " + num(w.scale));
  }
  if (!(std::isfinite(w.scale) && w.scale >= 0.0)) {
    return invalid("scale must be >= 0, got " + num(w.scale));
  }
  if (!std::isfinite(w.em_coarse_drop)) {
    return invalid("weights.em_coarse_drop must be finite, got " + num(w.em_coarse_drop));
  }
  if (w.em_coarse_patience < 0) {
    return invalid("weights.em_coarse_patience must be >= 0, got " +
                   std::to_string(w.em_coarse_patience));
  }
  if (!non_negative(w.em_coarse_motion)) {
    return invalid("weights.em_coarse_motion must be >= 0, got " + num(w.em_coarse_motion));
  }
  if (!non_negative(w.em_coarse_max_motion)) {
    return invalid("weights.em_coarse_max_motion must be >= 0, got " + num(w.em_coarse_max_motion));
  }
  if (!(w.em_min_shrink > 0.0 && w.em_min_shrink <= 1.0)) {
    return invalid("em_min_shrink must be in (0, 1], got " + num(w.em_min_shrink));
  }
  if (!(std::isfinite(w.em_min_scale) && w.em_min_scale >= 0.0)) {
    return invalid("em_min_scale must be >= 0, got " + num(w.em_min_scale));
  }
  if (o.error_model == ErrorModel::kPlane) {
    if (o.plane.normal_neighbours < 5 || o.plane.normal_neighbours > 64) {
      return invalid("plane.normal_neighbours must be in [5, 64], got " +
                     std::to_string(o.plane.normal_neighbours));
    }
    if (!(o.plane.epsilon > 0.0 && o.plane.epsilon <= 1.0)) {
      return invalid("plane.epsilon must be in (0, 1], got " + num(o.plane.epsilon));
    }
    if (!non_negative(o.plane.noise_floor)) {
      return invalid("plane.noise_floor must be >= 0, got " + num(o.plane.noise_floor));
    }
  }
  if (o.neighbour_cache < 0) {
    return invalid("neighbour_cache must be >= 0, got " + std::to_string(o.neighbour_cache));
  }
  if (o.coarse_stride != RegistrationOptions::kAutomatic &&
      (o.coarse_stride < 1 || o.coarse_stride > RegistrationOptions::kMaxCoarseStride)) {
    return invalid(
        "coarse_stride must be in [1, " + std::to_string(RegistrationOptions::kMaxCoarseStride) +
        "] or RegistrationOptions::kAutomatic (-1), got " + std::to_string(o.coarse_stride));
  }
  if (!non_negative(o.reassociate_motion)) {
    return invalid("reassociate_motion must be >= 0, got " + num(o.reassociate_motion));
  }
  if (!non_negative(o.source_voxel)) {
    return invalid("source_voxel must be >= 0, got " + num(o.source_voxel));
  }
  if (!non_negative(o.target_voxel)) {
    return invalid("target_voxel must be >= 0, got " + num(o.target_voxel));
  }
  if (o.num_threads < 1 || o.num_threads > 1024) {
    return invalid("num_threads must be in [1, 1024], got " + std::to_string(o.num_threads));
  }
  const LMOptions& lm = o.lm;
  if (lm.max_iterations < 1) {
    return invalid("lm.max_iterations must be >= 1, got " + std::to_string(lm.max_iterations));
  }
  if (!non_negative(lm.function_tolerance)) {
    return invalid("lm.function_tolerance must be >= 0, got " + num(lm.function_tolerance));
  }
  if (!(lm.fine_function_tolerance == LMOptions::kAutomatic ||
        non_negative(lm.fine_function_tolerance))) {
    return invalid("lm.fine_function_tolerance must be >= 0 or LMOptions::kAutomatic (-1), got " +
                   num(lm.fine_function_tolerance));
  }
  if (!non_negative(lm.gradient_tolerance)) {
    return invalid("lm.gradient_tolerance must be >= 0, got " + num(lm.gradient_tolerance));
  }
  if (!non_negative(lm.step_tolerance)) {
    return invalid("lm.step_tolerance must be >= 0, got " + num(lm.step_tolerance));
  }
  if (!finite_positive(lm.initial_lambda) || !(lm.max_lambda > lm.initial_lambda)) {
    return invalid("LM needs 0 < initial_lambda < max_lambda, got " + num(lm.initial_lambda) +
                   " and " + num(lm.max_lambda));
  }
  const TerminationCriteria& c = o.termination;
  if (c.criteria & ~std::uint32_t{0xF}) {
    return invalid("unknown termination criterion bits " + std::to_string(c.criteria));
  }
  if (c.max_iterations < 1) {
    return invalid("max_iterations must be >= 1, got " + std::to_string(c.max_iterations));
  }
  if (c.fixed_iterations < 1) {
    return invalid("fixed_iterations must be >= 1, got " + std::to_string(c.fixed_iterations));
  }
  if (!(std::isfinite(c.cost_drop_max_motion) && c.cost_drop_max_motion >= 0.0)) {
    return invalid("cost_drop_max_motion must be >= 0, got " + num(c.cost_drop_max_motion));
  }
  if (!std::isfinite(c.cost_drop_threshold)) {
    return invalid("cost_drop_threshold must be finite, got " + num(c.cost_drop_threshold));
  }
  if (c.cost_drop_patience < 0) {
    return invalid("termination.cost_drop_patience must be >= 0, got " +
                   std::to_string(c.cost_drop_patience));
  }
  if (c.mse_patience < 0) {
    return invalid("termination.mse_patience must be >= 0, got " + std::to_string(c.mse_patience));
  }
  if (c.successful_steps_patience < 0) {
    return invalid("termination.successful_steps_patience must be >= 0, got " +
                   std::to_string(c.successful_steps_patience));
  }
  if (!finite_positive(c.mse_ratio_threshold)) {
    return invalid("mse_ratio_threshold must be > 0, got " + num(c.mse_ratio_threshold));
  }
  return Status::Ok();
}

struct Registration::Impl {
  RegistrationOptions options;
  Status options_status;
  // Target, centred: target_centered = target - target_origin.
  PointCloud target_centered;
  Eigen::Vector3d target_origin = Eigen::Vector3d::Zero();
  std::size_t target_non_finite = 0;
  bool has_target = false;
  detail::KdTree tree;
  // Plane model only: the target's points and normals (the one copy of the normals).
  std::vector<detail::PlanePoint> target_plane_points;
  double target_surface_noise = 0.0;  // plane model only (target_normals.hpp)
  detail::PlaneModel plane;
  // Plane model with source normals only: the source's k-d tree and normals, one normal per
  // association slot.
  detail::KdTree source_tree;
  std::vector<Eigen::Vector3d> source_normals, pair_normals;
  // Per-alignment buffers, kept between calls so same-size registrations reuse them.
  PointCloud source_filtered, source_centered;
  // The coarse level (RegistrationOptions::coarse_stride > 1): every stride-th point of
  // source_centered, registered while the EM scale is coarse, and its source normals. It uses the
  // first rows of assoc and cache (spread_lists hands them to the full source).
  PointCloud coarse_centered;
  std::vector<Eigen::Vector3d> coarse_normals;
  std::vector<double> scratch;
  detail::SpatialSortScratch sort_scratch;
  detail::AssociationTable assoc;
  detail::NeighbourCache cache;  // candidate lists for exact incremental association
  detail::LMSolver lm;
};

Registration::Registration(const RegistrationOptions& options) : impl_(new Impl) {
  impl_->options = options;
  impl_->options_status = validate(options);
}
Registration::~Registration() = default;
Registration::Registration(Registration&&) noexcept = default;
Registration& Registration::operator=(Registration&&) noexcept = default;

const RegistrationOptions& Registration::options() const { return impl_->options; }

Status Registration::set_target(const PointCloud& target) {
  Impl& m = *impl_;
  m.has_target = false;
  if (!m.options_status.ok()) return m.options_status;
  PointCloud filtered;
  Status s =
      prepare_cloud(target, m.options.target_voxel, "target", &filtered, &m.target_non_finite);
  if (!s.ok()) return s;
  std::vector<double> scratch;
  s = center_cloud("target", target.size(), &filtered, &m.target_centered, &m.target_origin,
                   &m.target_non_finite, &scratch);
  if (!s.ok()) return s;
  // Z-order: a source point's neighbours lie near each other in memory (spatial_order.hpp).
  detail::SpatialSortScratch sort_scratch;
  detail::spatial_sort(&m.target_centered, nullptr, &sort_scratch);
  s = m.tree.build(m.target_centered);
  if (!s.ok()) return s;
  if (m.options.error_model == ErrorModel::kPlane) {
    std::vector<Eigen::Vector3d> normals;  // packed below, then freed
    std::vector<double> spread;
    detail::compute_normals(m.target_centered, m.tree, m.options.plane.normal_neighbours,
                            m.options.num_threads, &normals, &spread);
    m.target_surface_noise = detail::surface_noise(spread, &scratch);
    detail::pack_plane_points(m.target_centered, normals, m.options.plane.epsilon,
                              &m.target_plane_points);
    m.plane.points = &m.target_plane_points;
    m.plane.epsilon = m.options.plane.epsilon;
  }
  m.has_target = true;
  return Status::Ok();
}

RegistrationResult Registration::align(const PointCloud& source, const Eigen::Isometry3d& T_initial,
                                       const Eigen::Isometry3d* T_ground_truth) {
  Impl& m = *impl_;
  const RegistrationOptions& o = m.options;
  RegistrationResult result;
  // A refused input returns the initial guess, or the identity if the guess is not finite.
  if (T_initial.matrix().allFinite()) result.T_target_source = T_initial;
  auto refuse = [&](Status s) {
    result.status = std::move(s);
    result.stop_reason = StopReason::kInvalidInput;
    return result;
  };
  if (!m.options_status.ok()) return refuse(m.options_status);
  if (!m.has_target) {
    return refuse(Status(StatusCode::kEmptyCloud,
                         "no target: call set_target() first "
                         "(or it failed)"));
  }
  if (!T_initial.matrix().allFinite()) {
    return refuse(invalid("the initial guess has non-finite entries"));
  }
  {
    Status s = prepare_cloud(source, o.source_voxel, "source", &m.source_filtered,
                             &result.source_non_finite);
    if (!s.ok()) return refuse(s);
  }
  // Internal frame (see the file comment).
  Eigen::Vector3d source_origin;
  {
    Status s = center_cloud("source", source.size(), &m.source_filtered, &m.source_centered,
                            &source_origin, &result.source_non_finite, &m.scratch);
    if (!s.ok()) return refuse(s);
  }
  // Z-order: consecutive source points share their neighbours (spatial_order.hpp); both clouds
  // keep one order.
  detail::spatial_sort(&m.source_centered, &m.source_filtered, &m.sort_scratch);
  const PointCloud& src = m.source_filtered;
  const std::size_t n = src.size();
  result.source_points = n;
  result.target_points = m.target_centered.size();
  result.target_non_finite = m.target_non_finite;
  double extent_sq = 0.0;
  for (const Eigen::Vector3d& c : m.source_centered)
    extent_sq = std::max(extent_sq, c.squaredNorm());
  // Lengths the LM step tolerance, the coarse E-step scale and the motion guards are relative
  // to: the radius, unless the radius exceeds the source's extent (a radius of 1e6 m on a 2 m
  // cloud means "no radius", not "steps of 0.1 m are negligible").
  const double source_extent = std::sqrt(extent_sq);
  const double reference_length = std::min(o.radius, source_extent);
  const Eigen::Isometry3d to_target = translation(m.target_origin);
  const Eigen::Isometry3d from_source = translation(-source_origin);
  auto to_external = [&](const Eigen::Isometry3d& T) { return to_target * T * from_source; };
  Eigen::Isometry3d T = to_target.inverse() * T_initial * from_source.inverse();

  // Set-up allocations (reused when the next source has the same size).
  const int k = o.max_neighbours;
  const int cache_capacity = k + o.neighbour_cache;
  const bool use_cache =
      o.neighbour_cache > 0 && cache_capacity <= detail::NeighbourCache::kMaxCapacity;
  // set_target fitted the target's normals (the error model is fixed per Registration).
  const bool use_pair_normals = o.error_model == ErrorModel::kPlane && o.plane.source_normals;
  if (use_pair_normals) {
    Status s = m.source_tree.build(m.source_centered);
    if (!s.ok()) return refuse(s);
    detail::compute_normals(m.source_centered, m.source_tree, o.plane.normal_neighbours,
                            o.num_threads, &m.source_normals);
  }
  m.assoc.resize(n, k);
  if (use_cache) m.cache.resize(n, cache_capacity);  // also forgets the previous source's lists
  if (use_pair_normals) m.pair_normals.resize(m.assoc.index.size());
  // The coarse level: every stride-th point in Z-order, so spread over the whole cloud. The table
  // and cache shrink to its rows and grow back at the switch within their capacity (sized for n
  // just above): no allocation, no second table.
  const std::size_t stride = coarse_stride(o, n);
  bool use_coarse = stride > 1;  // dropped if the coarse level finds no pair (below)
  if (use_coarse) {
    const std::size_t n_coarse = (n + stride - 1) / stride;
    m.coarse_centered.resize(n_coarse);
    if (use_pair_normals) m.coarse_normals.resize(n_coarse);
    for (std::size_t i = 0; i < n_coarse; ++i) {
      m.coarse_centered[i] = m.source_centered[i * stride];
      if (use_pair_normals) m.coarse_normals[i] = m.source_normals[i * stride];
    }
    m.assoc.resize(n_coarse, k);
    if (use_cache) m.cache.resize(n_coarse, cache_capacity);
  }
  m.plane.pair_normals = use_pair_normals ? &m.pair_normals : nullptr;
  m.lm.resize(n, k);
  const CloudMoments moments = compute_moments(src);
  TerminationMonitor monitor(o.termination, moments, T_initial);
  if (o.record_history)
    result.history.reserve(static_cast<std::size_t>(std::min(o.termination.max_iterations, 1000)));

  detail::LMProblem problem;
  problem.target = &m.target_centered;
  problem.assoc = &m.assoc;
  problem.weights.model = o.weights.model;
  problem.weights.dof = o.weights.dof;
  problem.num_threads = o.num_threads;
  problem.step_reference = reference_length;
  problem.source_extent = source_extent;

  // E-step scale s (weights.hpp); with the plane model's noise floor, s >= noise_floor x the
  // target's surface noise as well as em_min_scale. The point model's surface noise is 0, so the
  // product is 0 or (an unvalidated option times 0) NaN: no floor either way.
  WeightOptions weights = o.weights;
  const double noise_floor = o.plane.noise_floor * m.target_surface_noise;
  if (std::isfinite(noise_floor)) {
    weights.em_min_scale = std::max(weights.em_min_scale, noise_floor);
  }
  detail::ScaleSchedule scale(weights, reference_length);
  // The table holds the coarse level's rows until the coarse phase ends (coarse_stride() is 1
  // without the EM scale, whose schedule starts coarse).
  assert(!use_coarse || scale.coarse());
  const double fine_tolerance = fine_phase_tolerance(o);
  const double radius_sq = o.radius * o.radius;

  using Clock = std::chrono::steady_clock;
  StopReason reason = StopReason::kNone;
  Eigen::Isometry3d T_associated = T;  // pose of the last association
  bool coarse_associated = false;      // the table holds the coarse level's rows
  // Association (paper Sec. 3.1) at T of the coarse level or of every point, into m.assoc (and
  // each pair's normal with source normals, frozen until the next association).
  auto associate_at = [&](bool coarse) {
    const PointCloud& cloud = coarse ? m.coarse_centered : m.source_centered;
    // From the coarse level to every point: the table (and the lists) grow, the coarse points
    // keeping theirs.
    const bool spread = coarse_associated && !coarse;
    if (use_cache) {
      if (spread) detail::spread_lists(stride, n, &m.cache, &m.assoc);
      detail::associate_cached(m.tree, m.target_centered, cloud, T, o.radius, o.num_threads,
                               &m.cache, &m.assoc);
    } else {
      if (spread) m.assoc.resize(n, k);
      detail::associate(m.tree, cloud, T, radius_sq, o.num_threads, &m.assoc);
    }
    T_associated = T;
    coarse_associated = coarse;
    if (use_pair_normals) {
      detail::compute_pair_normals(m.assoc, m.target_plane_points,
                                   coarse ? m.coarse_normals : m.source_normals, T.linear(),
                                   o.num_threads, &m.pair_normals);
    }
  };
  for (int t = 1; reason == StopReason::kNone; ++t) {
    const Clock::time_point start = Clock::now();
    bool coarse = use_coarse && scale.coarse();
    // Re-associate unless no source point can have moved more than reassociate_motion x radius
    // since the last association: a point x moves by
    // |(R - R_a) x + (t - t_a)| <= |R - R_a|_2 |x| + |t - t_a|, |R - R_a|_2 = 2 sin(angle / 2).
    // Fresh lists also when the termination monitor or the scale schedule asks: a streak toward
    // a stop or toward the coarse phase's end is running, or the last iteration reused lists and
    // would have counted toward one. Both count only iterations on fresh associations
    // (termination.hpp, scale_schedule.hpp).
    bool reassociate = t == 1 || coarse != coarse_associated || o.reassociate_motion <= 0.0 ||
                       monitor.wants_fresh_lists() || scale.wants_fresh_lists();
    if (!reassociate) {
      const Eigen::AngleAxisd rotation(T.linear() * T_associated.linear().transpose());
      const double bound = 2.0 * std::sin(0.5 * std::abs(rotation.angle())) * source_extent +
                           (T.translation() - T_associated.translation()).norm();
      reassociate = !(bound <= o.reassociate_motion * reference_length);
    }
    if (reassociate) {
      associate_at(coarse);
      // The coarse level found no pair: its points may miss a small overlap that others reach.
      // Every point from now on.
      if (coarse && m.assoc.pairs == 0) {
        use_coarse = coarse = false;
        associate_at(false);
      }
    }
    const PointCloud& cloud = coarse ? m.coarse_centered : m.source_centered;
    problem.source = &cloud;
    result.matched_source_points = m.assoc.matched;
    result.correspondences = m.assoc.pairs;
    if (m.assoc.pairs == 0) {
      reason = StopReason::kNoCorrespondences;
      if (t == 1) {
        result.status =
            Status(StatusCode::kNoCorrespondences,
                   "no source point has a target point within radius " + num(o.radius) +
                       "; source (moved by the initial guess) spans " + extent(src, T_initial) +
                       ", target spans " + extent(m.target_centered, to_target));
      }
      break;
    }
    const double scale_sq = scale.scale_sq();
    // Plane model: point-to-point while the scale is coarse (wider basin), then plane-aware.
    problem.plane =
        o.error_model == ErrorModel::kPlane && !(o.plane.point_while_coarse && scale.coarse())
            ? &m.plane
            : nullptr;
    // 1 / s^2, finite even when s^2 underflows (radius or scale ~1e-300): exact associations
    // then keep z = 0 (not 0 * Inf = NaN).
    problem.weights.inv_scale_sq = std::min(1.0 / scale_sq, std::numeric_limits<double>::max());

    // EM fine phase: the looser inner tolerance, if any (lm.hpp).
    LMOptions lm_options = o.lm;
    if (fine_tolerance > 0.0 && !scale.coarse()) lm_options.function_tolerance = fine_tolerance;
    const LMSummary lm = m.lm.solve(lm_options, problem, &T);
    result.lm_iterations += lm.iterations;
    result.lm_successful_steps += lm.successful_steps;
    if (t == 1) result.initial_cost = lm.initial_cost;
    result.final_cost = lm.final_cost;
    result.T_target_source = to_external(T);
    result.iterations = t;

    IterationReport report;
    report.iteration = t;
    report.lm = lm;
    report.T_target_source = result.T_target_source;
    report.scale_settling = scale.settling();
    report.motion_reference = reference_length;
    report.lists_reused = !reassociate;
    reason = lm.termination == LMTermination::kNumericalFailure ? StopReason::kNumericalFailure
                                                                : monitor.update(report);
    if (reason == StopReason::kNumericalFailure) {
      result.status = Status(StatusCode::kNumericalFailure,
                             "non-finite cost or step in outer iteration " + std::to_string(t));
    }
    // EM estimate of s^2 at the final pose: sum w r / (3 N) = 2 final_cost / (3 N).
    scale.update(monitor.last_cost_drop(), std::sqrt(monitor.last_mse_prev()),
                 2.0 * lm.final_cost / (3.0 * static_cast<double>(m.assoc.matched)),
                 report.lists_reused);
    if (o.record_history || o.on_iteration) {
      IterationRecord r;
      r.iteration = t;
      r.successful_steps = lm.successful_steps;
      r.unsuccessful_steps = lm.unsuccessful_steps;
      r.initial_cost = lm.initial_cost;
      r.final_cost = lm.final_cost;
      r.cost_drop = monitor.last_cost_drop();
      r.mse_prev = monitor.last_mse_prev();
      if (T_ground_truth != nullptr) {
        r.mse_ground_truth = mse_between(moments, result.T_target_source, *T_ground_truth);
        r.benchmark_error = benchmark_error(src, *T_ground_truth, result.T_target_source);
      }
      r.scale = std::sqrt(scale_sq);
      r.correspondences = m.assoc.pairs;
      r.matched_source_points = m.assoc.matched;
      r.lists_reused = !reassociate;
      r.T_target_source = result.T_target_source;
      r.time_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      if (o.on_iteration && !o.on_iteration(r) && reason == StopReason::kNone) {
        reason = StopReason::kCancelled;
      }
      if (o.record_history) result.history.push_back(r);
    }
  }
  result.stop_reason = reason;
  result.scale = std::sqrt(scale.scale_sq());
  result.target_surface_noise = m.target_surface_noise;  // 0 with the point model

  // Information at the final pose. With the plane model, the directions the surfaces leave
  // free: eigenvalues of the surface-normal information with rotations scaled by the source's
  // RMS radius (so both blocks are in cloud units^2) below kDegenerateRatio of the largest.
  // Measured ratios (scratch run, identical clouds moved by 0.02 rad / 1.5 cm): the free
  // directions of a plane 0, of a cylinder 3.1e-4 and 3.5e-4, of a sphere 2.7e-4 to 3.4e-4 (PCA
  // normals of sampled curved surfaces are not exact); the smallest constrained one 0.10 on the
  // bunny, 0.098 on the lidar pair, 0.26 on the cylinder. 1e-2 sits 30x and 10x from both.
  // Judged on the target's normals also with source normals: the null directions are those the
  // target's surfaces leave free, whatever normal the pairs use (result.information, from the
  // solver, does use the pair normals).
  constexpr double kDegenerateRatio = 1e-2;
  result.information = m.lm.last().H;
  if (o.error_model == ErrorModel::kPlane && result.iterations > 0) {
    // The points the table holds (the coarse level's after a stop in the coarse phase).
    const detail::Matrix6d H_normal = detail::NormalEquations::normal_information(
        coarse_associated ? m.coarse_centered : m.source_centered, m.assoc, T,
        m.lm.weights().data(), m.target_plane_points);
    const double rms = std::sqrt(std::max(moments.covariance.trace(), 1e-300));
    detail::Vector6d scaling;
    scaling << rms, rms, rms, 1.0, 1.0, 1.0;
    const detail::Matrix6d normalised =
        scaling.cwiseInverse().asDiagonal() * H_normal * scaling.cwiseInverse().asDiagonal();
    if (normalised.allFinite() && normalised.diagonal().maxCoeff() > 0.0) {
      Eigen::SelfAdjointEigenSolver<detail::Matrix6d> eig(normalised, Eigen::EigenvaluesOnly);
      const detail::Vector6d ev = eig.eigenvalues();
      result.degenerate_directions =
          static_cast<int>((ev.array() < kDegenerateRatio * ev.maxCoeff()).count());
    }
  }
  return result;
}

RegistrationResult align(const PointCloud& source, const PointCloud& target,
                         const RegistrationOptions& options, const Eigen::Isometry3d& T_initial,
                         const Eigen::Isometry3d* T_ground_truth) {
  Registration registration(options);
  Status s = registration.set_target(target);
  if (!s.ok()) {
    RegistrationResult result;
    result.status = s;
    result.stop_reason = StopReason::kInvalidInput;
    if (T_initial.matrix().allFinite()) result.T_target_source = T_initial;
    return result;
  }
  return registration.align(source, T_initial, T_ground_truth);
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
