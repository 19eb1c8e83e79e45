// registration.cpp - the outer loop (paper Sec. 3.2): associate, solve the inner problem (E-step
// weights and LM, Sec. 3.1), ask the termination criterion; set-up and summary in named helpers.
// The solver works in the internal frame of cloud_preparation.hpp (centred, lengths in the unit
// u): poses, costs and scales are mapped back to the user's frame and units for the result.
#include "ppcr/registration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "association/associator.hpp"
#include "association/kdtree.hpp"
#include "association/spatial_order.hpp"
#include "common/format.hpp"
#include "common/parallel.hpp"
#include "ppcr/metrics.hpp"
#include "ppcr/se3.hpp"
#include "preparation/cloud_preparation.hpp"
#include "preparation/pca_normals.hpp"
#include "preparation/point_spacing.hpp"
#include "quality/alignment_quality.hpp"
#include "quality/covariance.hpp"
#include "quality/degeneracy.hpp"
#include "quality/verdict.hpp"
#include "registration/pose_acceleration.hpp"
#include "registration/resolve_options.hpp"
#include "registration/scale_schedule.hpp"
#include "registration/termination.hpp"
#include "solver/lm_solver.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kSpacingSamples = 4096;  // enough for a median, cheap on any cloud
constexpr double kCloseSpacings = 2.0;         // RegistrationResult::close_fraction's distance...
constexpr double kNearSpacings = 8.0;          // ...and the reach of the points it is taken over
constexpr double kAccelerationGain = 10.0;     // an extrapolation moves at most 10 last steps
using detail::num;

// Poses and lengths between the user's frames and units and the internal ones
// (cloud_preparation.hpp): T_user = Tr(o_target) S_u T S_u^-1 Tr(-o_source).
struct Frame {
  Eigen::Vector3d target_origin, source_origin;
  double unit;
  Eigen::Isometry3d external(const Eigen::Isometry3d& T) const {
    Eigen::Isometry3d E = T;
    E.translation() = unit * T.translation() + target_origin - T.linear() * source_origin;
    return E;
  }
  Eigen::Isometry3d internal(const Eigen::Isometry3d& T) const {
    Eigen::Isometry3d I = T;
    I.translation() = (T.translation() - target_origin + T.linear() * source_origin) / unit;
    return I;
  }
  double length(double internal_length) const { return unit * internal_length; }
  double area(double internal_area) const { return unit * unit * internal_area; }
  // The information of a twist (omega, v): v in cloud units is u times v in internal units, and
  // the cost (squared lengths) u^2 times the internal one, so H = S H_internal S, S = diag(u I, I).
  detail::Matrix6d information(const detail::Matrix6d& H) const {
    detail::Matrix6d E = H;
    E.topLeftCorner<3, 3>() *= unit * unit;
    E.topRightCorner<3, 3>() *= unit;
    E.bottomLeftCorner<3, 3>() *= unit;
    return E;
  }
  // The covariance of a twist about the internal origin (the target's median point) as the
  // covariance of the twist (omega, v') about the target frame's origin: v' = u v + o x omega
  // (the adjoint of the translation by o = target_origin), C' = A C A^T.
  detail::Matrix6d covariance(const detail::Matrix6d& C) const {
    detail::Matrix6d A = detail::Matrix6d::Identity();
    A.bottomRightCorner<3, 3>() *= unit;
    A.bottomLeftCorner<3, 3>() = se3::skew(target_origin);
    return detail::positive_semidefinite(A * C * A.transpose());
  }
};

// The box a prepared cloud's points span in the user's frame after T, for messages.
std::string extent(const detail::PreparedCloud& cloud, const Eigen::Isometry3d& T) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
  for (std::size_t i = 0; i < cloud.centered.size(); ++i) {
    const Eigen::Vector3d q = T * cloud.user_point(i);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  return "[" + num(lo.x()) + ", " + num(hi.x()) + "] x [" + num(lo.y()) + ", " + num(hi.y()) +
         "] x [" + num(lo.z()) + ", " + num(hi.z()) + "]";
}

// 1 / s^2, finite even when s^2 underflows (radius or scale ~1e-300): exact associations then
// keep z = 0 (not 0 * Inf = NaN).
double inverse_sq(double scale_sq) {
  return std::min(1.0 / scale_sq, std::numeric_limits<double>::max());
}

void set_verdict(RegistrationResult* result) {
  const detail::Verdict v = detail::judge(*result);
  result->quality = v.quality;
  result->quality_reason = v.reason;
}

// A refused input returns the initial guess, or the identity if the guess is not finite.
RegistrationResult refused(const Status& s, const Eigen::Isometry3d& T_initial,
                           RegistrationResult result) {
  result.status = s;
  result.stop_reason = StopReason::kInvalidInput;
  result.T_target_source =
      T_initial.matrix().allFinite() ? T_initial : Eigen::Isometry3d::Identity();
  set_verdict(&result);
  return result;
}

// A cloud's plane fits summarised (pca_normals.hpp): the medians of their spread and reach, and
// the point spacing (point_spacing.hpp), internal unit; surface noise and reach 0 without fits.
struct SurfaceFits {
  double spacing = 0.0;
  double surface_noise = 0.0;
  double reach = 0.0;
};

}  // namespace

struct Registration::Impl {
  explicit Impl(const RegistrationOptions& o)
      : options(o),
        options_status(validate(o)),
        parallel(options_status.ok() ? o.num_threads : 1) {}

  RegistrationOptions options;  // the user's
  RegistrationOptions solver;   // the same in the internal unit of the current target
  Status options_status;
  // Up to options.num_threads threads (1 for refused options), the workers started with it.
  detail::Parallel parallel;
  bool has_target = false;
  Status target_status;  // the last set_target()'s or set_target_to_source()'s, for align()
  detail::PreparedCloud target;
  detail::KdTree tree;
  // Plane model only: the target's points and normals, and which points lie on its boundary
  // (boundary.hpp; with expert.reject_boundary).
  detail::Buffer<detail::PlanePoint> target_plane_points;
  detail::Buffer<std::uint8_t> target_boundary;
  detail::Buffer<detail::PlaneInformation> target_plane_information;  // without pair normals
  // The target's spacing, and with the plane model its surface noise and the normal fits' typical
  // reach (pca_normals.hpp); internal unit.
  SurfaceFits target_fits;
  double radius = 0.0;  // the radius used, cloud units (the user's, or automatic)
  detail::PlaneModel plane;
  // Per source; kept between calls so same-size registrations reuse the buffers.
  detail::PreparedCloud source;
  detail::KdTree source_tree;
  std::vector<Eigen::Vector3d> source_normals;
  detail::Buffer<std::uint8_t> source_boundary;
  SurfaceFits source_fits;  // with pair_normals(), for set_target_to_source()
  // `source` (with pair_normals(): source_tree, source_normals, source_fits) prepared in full by
  // the last align(), not yet made the target.
  bool has_source = false;
  detail::SpatialSortScratch sort_scratch;
  detail::Associator associator;
  detail::LMSolver lm;
  std::vector<double> quality_scratch;
  std::vector<detail::Matrix6d> information_blocks;         // normal_information's per-block sums
  std::vector<detail::CovarianceSums> covariance_clusters;  // covariance_sums' per cluster

  struct Run;
  bool automatic_radius() const { return options.radius == RegistrationOptions::kAutomaticRadius; }
  // The radius a target's internal unit is taken from: an automatic one is not known before the
  // target's spacing, so the unit is then the target's extent.
  double unit_radius() const { return automatic_radius() ? HUGE_VAL : options.radius; }
  bool plane_model() const { return options.error_model == ErrorModel::kPlane; }
  // Plane model with source normals: pairs use both clouds' normals (pair_normals.hpp).
  bool pair_normals() const { return plane_model() && options.expert.source_normals; }
  SurfaceFits fit_surface(const PointCloud& cloud, const detail::KdTree& index,
                          std::vector<Eigen::Vector3d>* normals,
                          detail::Buffer<std::uint8_t>* boundary) const;
  Status make_target(const PointCloud& cloud, double voxel);
  void order(detail::PreparedCloud* cloud);
  Status take_source();
  Status index_target();
  Status adopt_target(const SurfaceFits& fits, const std::vector<Eigen::Vector3d>& normals);
  Status check_input(const Eigen::Isometry3d& T_initial) const;
  Status prepare_source(const PointCloud& cloud, RegistrationResult* result);
  RegistrationResult align(const PointCloud& cloud, const Eigen::Isometry3d& T_initial,
                           PointCloud* consumed);
  RegistrationResult iterate(const Eigen::Isometry3d& T_initial, RegistrationResult result);
  detail::LMProblem problem(double step_reference, double source_extent) const;
  Run start(const Eigen::Isometry3d& T_initial, RegistrationResult* result);
  const detail::AssociationTable& associate(Run* run, bool coarse, const Eigen::Isometry3d& T,
                                            Eigen::Isometry3d* T_start);
  LMSummary solve(Run* run, bool coarse, Eigen::Isometry3d* T);
  Status no_pairs(const Eigen::Isometry3d& T_initial) const;
  IterationRecord record(int t, bool coarse, double scale_sq, const LMSummary& summary,
                         const Run& run, const Eigen::Isometry3d& T_target_source,
                         Clock::time_point start) const;
  void summarise(StopReason reason, const Eigen::Isometry3d& T, const Run& run,
                 RegistrationResult* result);
  detail::Matrix6d covariance(const Eigen::Isometry3d& T, const Run& run,
                              const detail::Matrix6d* H_normal);
};

Registration::Registration(const RegistrationOptions& options) : impl_(new Impl(options)) {}
Registration::~Registration() = default;
Registration::Registration(Registration&&) noexcept = default;
Registration& Registration::operator=(Registration&&) noexcept = default;

const RegistrationOptions& Registration::options() const { return impl_->options; }

// A refused target leaves none: align() is then refused with the same status.
Status Registration::set_target(const PointCloud& target) {
  Impl& m = *impl_;
  m.has_target = m.has_source = false;
  if (!m.options_status.ok()) return m.options_status;
  return m.target_status = m.make_target(target, m.options.target_voxel);
}

Status Registration::set_target_to_source() {
  Impl& m = *impl_;
  m.has_target = false;
  if (!m.options_status.ok()) return m.options_status;
  return m.target_status = m.take_source();
}

Status Registration::Impl::take_source() {
  if (!has_source) {
    return Status(StatusCode::kEmptyCloud,
                  "set_target_to_source: no source to take: the last align() did not prepare "
                  "one, or it was taken already (set_target() or set_target_to_source() since)");
  }
  if (options.source_voxel != options.target_voxel) {
    return Status(StatusCode::kInvalidArgument,
                  "set_target_to_source: source_voxel (" + num(options.source_voxel) +
                      ") differs from target_voxel (" + num(options.target_voxel) +
                      "): the source was filtered as a source; call set_target() with the cloud");
  }
  has_source = false;
  // The source was centred, divided by the previous target's unit and Z-ordered as a target
  // would be. Any unit serves (internal_unit() keeps the numbers near 1), so it is kept unless
  // it is more than 2x off the cloud's own; then the target is prepared again from the filtered
  // points, mapped back to the user's frame to rounding (a chain of targets never drifts from
  // its clouds' scale).
  const double ratio = detail::internal_unit(unit_radius(), source.extent) / source.unit;
  if (!(ratio >= 0.5 && ratio <= 2.0)) {
    PointCloud filtered(source.centered.size());  // back in the user's frame, to rounding
    for (std::size_t i = 0; i < filtered.size(); ++i) filtered[i] = source.user_point(i);
    const Status s = make_target(filtered, 0.0);
    target.leaf = source.leaf;  // filtered already: the leaf it was filtered with
    target.dropped = source.dropped;
    target.duplicates += source.duplicates;  // with any the new unit's rounding merged
    return s;
  }
  std::swap(target, source);
  if (!pair_normals()) return index_target();  // align() fitted no source normals
  std::swap(tree, source_tree);
  std::swap(target_boundary, source_boundary);
  return adopt_target(source_fits, source_normals);
}

// Prepares `cloud` as the target: filtered, centred in its own unit, ordered (order()), then
// index_target().
Status Registration::Impl::make_target(const PointCloud& cloud, double voxel) {
  const Status s = detail::prepare_cloud(cloud, voxel, unit_radius(), 0.0, "target", &target);
  if (!s.ok()) return s;
  order(&target);
  return index_target();
}

// Z-orders a prepared cloud (a point's neighbours then lie near each other in memory:
// spatial_order.hpp) and keeps one of each set of equal points. Copies add no sample of the
// surface, only ties: every copy has the same neighbours, and a search visits each copy within
// its bound (a scanner's invalid returns, thousands at its origin, made a full-resolution scan
// pair take twice as long).
void Registration::Impl::order(detail::PreparedCloud* cloud) {
  detail::spatial_sort(&cloud->centered, nullptr, &sort_scratch, &parallel);
  cloud->duplicates = detail::drop_duplicates(&cloud->centered);
}

// The prepared, Z-ordered target's tree and (plane model) normal fits, then adopt_target().
Status Registration::Impl::index_target() {
  const Status s = tree.build(target.centered);
  if (!s.ok()) return s;
  std::vector<Eigen::Vector3d> normals;  // packed by adopt_target, then freed
  return adopt_target(
      fit_surface(target.centered, tree, plane_model() ? &normals : nullptr, &target_boundary),
      normals);
}

// The plane fit of each point of `cloud` (internal frame, `index` built over it) into *normals
// (no fits when null), with expert.reject_boundary its boundary points into *boundary (else
// emptied), summarised: the medians of the fits, and the spacing from the fits' nearest
// neighbours when compute_normals kept them, otherwise from queries of `index`. The other
// per-point statistics are freed, not kept.
SurfaceFits Registration::Impl::fit_surface(const PointCloud& cloud, const detail::KdTree& index,
                                            std::vector<Eigen::Vector3d>* normals,
                                            detail::Buffer<std::uint8_t>* boundary) const {
  detail::Buffer<double> spread, reach, nearest_sq;
  const bool boundaries = normals != nullptr && options.expert.reject_boundary;
  if (!boundaries) boundary->clear();
  if (normals != nullptr) {
    detail::compute_normals(cloud, index, options.expert.normal_neighbours, &parallel, normals,
                            &spread, &reach, &nearest_sq, boundaries ? boundary : nullptr);
  }
  std::vector<double> scratch;  // the spacing's samples
  SurfaceFits summary;
  summary.spacing = detail::median_spacing(cloud, index, kSpacingSamples, &nearest_sq, &scratch);
  summary.surface_noise = detail::upper_median(&spread);
  summary.reach = detail::upper_median(&reach);
  return summary;
}

// Makes the prepared, indexed target current: the solver's options in its unit, the radius
// (automatic: from its spacing), the plane points from its normals.
Status Registration::Impl::adopt_target(const SurfaceFits& fits,
                                        const std::vector<Eigen::Vector3d>& normals) {
  target_fits = fits;
  solver = detail::in_internal_units(options, target.unit);
  if (automatic_radius()) {
    if (!(fits.spacing > 0.0)) {
      return Status(StatusCode::kInvalidArgument,
                    "radius: an automatic radius needs the target's point spacing, and its points "
                    "all coincide; give the radius");
    }
    solver.radius = RegistrationOptions::kAutomaticRadiusSpacings * fits.spacing;
  }
  radius = solver.radius * target.unit;
  if (plane_model()) {
    // The pair normals form each pair's information in the pass: no per-target-point moments.
    auto* information = pair_normals() ? nullptr : &target_plane_information;
    detail::pack_plane_points(target.centered, normals, solver.expert.plane_epsilon, &parallel,
                              &target_plane_points, information);
    plane.points = &target_plane_points;
    plane.information = information;
    plane.epsilon = solver.expert.plane_epsilon;
  }
  associator.set_target(&tree, &target.centered,
                        target_boundary.empty() ? nullptr : target_boundary.data());
  has_target = true;
  return Status::Ok();
}

Status Registration::Impl::check_input(const Eigen::Isometry3d& T_initial) const {
  if (!options_status.ok()) return options_status;
  if (!has_target) {
    return target_status.ok()
               ? Status(StatusCode::kEmptyCloud, "no target: call set_target() first")
               : target_status;
  }
  if (!T_initial.matrix().allFinite()) {
    return Status(StatusCode::kInvalidArgument, "the initial guess has non-finite entries");
  }
  return Status::Ok();
}

// Filters, centres and Z-orders the source (consecutive points then share their neighbours:
// spatial_order.hpp), and fits its normals when the pairs use them.
Status Registration::Impl::prepare_source(const PointCloud& cloud, RegistrationResult* result) {
  Status s =
      detail::prepare_cloud(cloud, options.source_voxel, radius, target.unit, "source", &source);
  result->source_non_finite = source.dropped;
  if (!s.ok()) return s;
  order(&source);
  result->source_duplicates = source.duplicates;
  result->target_duplicates = target.duplicates;
  result->source_points = source.centered.size();
  result->target_points = target.centered.size();
  result->target_non_finite = target.dropped;
  result->target_surface_noise = target.unit * target_fits.surface_noise;
  result->target_spacing = target.unit * target_fits.spacing;
  result->radius = radius;
  result->source_voxel = source.leaf;
  result->target_voxel = target.leaf;
  if (pair_normals()) {
    s = source_tree.build(source.centered);
    if (!s.ok()) return s;
    // With the fits' medians, so that set_target_to_source() can make this source the target.
    source_fits = fit_surface(source.centered, source_tree, &source_normals, &source_boundary);
  }
  has_source = true;
  return Status::Ok();
}

detail::LMProblem Registration::Impl::problem(double step_reference, double source_extent) const {
  detail::LMProblem p;
  p.target = &target.centered;
  p.assoc = &associator.table();
  p.weights = detail::weight_params(solver);
  p.plane = plane_model() ? &plane : nullptr;
  p.parallel = &parallel;
  p.step_reference = step_reference;
  p.source_extent = source_extent;
  return p;
}

// Everything one align() needs beside the clouds, set up before the loop.
struct Registration::Impl::Run {
  Frame frame;
  double reference_length;  // the radius, or the source's extent if smaller (internal unit)
  CloudMoments moments;     // of the internal source, for the MSE w.r.t. the previous pose
  double source_rms;        // its RMS radius (the length of rotations: acceleration, degeneracy)
  TerminationMonitor monitor;
  detail::ScaleSchedule scale;
  detail::LMProblem problem;
  detail::PoseAcceleration acceleration;  // of the coarse phase
  LMOptions coarse_lm;
  double fine_tolerance;      // the inner LM's tolerance in the EM fine phase (0: none)
  double previous_tolerance;  // the last solve's
};

// Sizes and configures every unit for the prepared source, in the internal frame. Lengths are
// relative to the radius unless it exceeds the source's extent (a radius of 1e6 m on a 2 m cloud
// means "no radius", not "steps of 0.1 m are negligible").
Registration::Impl::Run Registration::Impl::start(const Eigen::Isometry3d& T_initial,
                                                  RegistrationResult* result) {
  const RegistrationOptions& o = solver;
  result->T_target_source = T_initial;  // until an iteration moves it
  double extent_sq = 0.0;
  for (const Eigen::Vector3d& c : source.centered) extent_sq = std::max(extent_sq, c.squaredNorm());
  const double source_extent = std::sqrt(extent_sq);
  const double reference_length = std::min(o.radius, source_extent);
  const std::size_t n = source.centered.size();
  const detail::Associator::Settings settings{o.max_neighbours, o.radius, o.expert.neighbour_cache,
                                              detail::coarse_stride(o, n), &parallel};
  associator.prepare(settings, source.centered, pair_normals() ? &source_normals : nullptr);
  plane.pair_source = associator.pair_normal_source();
  lm.resize(n, o.max_neighbours);
  // For every point, also when a run that ends on the coarse level came first (allocation-free
  // after the first call).
  information_blocks.reserve(detail::block_count(n, detail::NormalEquations::kBlockSize));
  covariance_clusters.reserve(detail::block_count(n, detail::kClusterPoints));
  if (o.record_history) result->history.reserve(std::min<std::size_t>(o.max_iterations, 1000));
  const CloudMoments moments = compute_moments(source.centered);
  const double source_rms = std::sqrt(std::max(moments.covariance.trace(), 1e-300));
  const LMOptions coarse_lm = detail::lm_options(o);
  const Frame frame{target.origin, source.origin, target.unit};
  return Run{
      frame,
      reference_length,
      moments,
      source_rms,
      TerminationMonitor(detail::termination_criteria(o), moments, frame.internal(T_initial)),
      detail::ScaleSchedule(detail::schedule_options(o, target_fits.surface_noise),
                            reference_length),
      problem(reference_length, source_extent),
      detail::PoseAcceleration(o.expert.acceleration_memory, source_rms, kAccelerationGain),
      coarse_lm,
      detail::fine_function_tolerance(o),
      coarse_lm.function_tolerance};
}

// Up to k target points within the radius of each source point at *T_start (Sec. 3.1). A start
// extrapolated beyond every target point falls back to the last solved pose T.
const detail::AssociationTable& Registration::Impl::associate(Run* run, bool coarse,
                                                              const Eigen::Isometry3d& T,
                                                              Eigen::Isometry3d* T_start) {
  // Rows beyond the target's boundary are left out once the EM scale's coarse phase has brought
  // the clouds together: before, an edge's pairs are part of what pulls the source into place
  // (measured: docs/BENCHMARK.md, "Rows beyond the target's boundary"). The other scale modes
  // have no such phase, and were not measured with the rule: never.
  const bool leave_out_boundary =
      options.expert.scale_mode == ScaleMode::kEM && !run->scale.coarse();
  if (associator.find_from(coarse, T, T_start, leave_out_boundary)) run->acceleration.reset();
  return associator.table();
}

// The inner problem of one outer iteration (Sec. 3.1): E-step weights at the scale s (eq. 3-4)
// and LM on SE(3), the weights refreshed at every accepted step. After a change of tolerance (the
// EM fine phase's looser one) the first step is evaluated, so the cost drop the criterion reads
// is measured, never the 0 of a solve that ended on an unevaluated step.
LMSummary Registration::Impl::solve(Run* run, bool coarse, Eigen::Isometry3d* T) {
  run->problem.source = &associator.points();
  run->problem.weights.inv_scale_sq = inverse_sq(run->scale.scale_sq());
  LMOptions lm_options = run->coarse_lm;
  if (run->fine_tolerance > 0.0 && !coarse) lm_options.function_tolerance = run->fine_tolerance;
  lm_options.evaluate_first_step = lm_options.function_tolerance != run->previous_tolerance;
  run->previous_tolerance = lm_options.function_tolerance;
  return lm.solve(lm_options, run->problem, T);
}

Status Registration::Impl::no_pairs(const Eigen::Isometry3d& T_initial) const {
  const bool automatic = automatic_radius();
  return Status(StatusCode::kNoCorrespondences,
                "no source point has a target point within radius " + num(radius) +
                    (automatic ? " (automatic: give a radius that covers the misalignment)" : "") +
                    "; source (moved by the initial guess) spans " + extent(source, T_initial) +
                    ", target spans " + extent(target, Eigen::Isometry3d::Identity()));
}

RegistrationResult Registration::align(const PointCloud& source,
                                       const Eigen::Isometry3d& T_initial) {
  return impl_->align(source, T_initial, nullptr);
}

RegistrationResult Registration::align(PointCloud&& source, const Eigen::Isometry3d& T_initial) {
  return impl_->align(source, T_initial, &source);
}

// Checks the input and prepares the source, frees `consumed` (the caller's cloud, when it handed
// it over: the iterations need only the prepared copy), then iterates or returns the refusal.
RegistrationResult Registration::Impl::align(const PointCloud& cloud,
                                             const Eigen::Isometry3d& T_initial,
                                             PointCloud* consumed) {
  RegistrationResult result;
  has_source = false;  // until this call's source is prepared
  Status s = check_input(T_initial);
  if (s.ok()) s = prepare_source(cloud, &result);
  if (consumed != nullptr) PointCloud().swap(*consumed);
  if (!s.ok()) return refused(s, T_initial, std::move(result));
  return iterate(T_initial, std::move(result));
}

// The outer loop (Sec. 3): associate, solve, ask the criterion, update the EM scale.
RegistrationResult Registration::Impl::iterate(const Eigen::Isometry3d& T_initial,
                                               RegistrationResult result) {
  Run run = start(T_initial, &result);
  Eigen::Isometry3d T = run.frame.internal(T_initial);  // the last solved pose
  Eigen::Isometry3d T_next = T;                         // where the next iteration starts
  StopReason reason = StopReason::kNone;
  for (int t = 1; reason == StopReason::kNone; ++t) {
    const Clock::time_point start = Clock::now();
    const bool coarse = run.scale.coarse();
    // The coarse level while the EM scale settles (coarse, or shrinking at its limit); the
    // associator never returns to it once it has associated every point.
    const detail::AssociationTable& pairs = associate(&run, run.scale.settling(), T, &T_next);
    // Every row with pairs, the rows left out beyond the target's boundary too.
    result.matched_source_points = pairs.all_matched();
    result.correspondences = pairs.all_pairs();
    if (pairs.pairs == 0) {
      reason = StopReason::kNoCorrespondences;
      if (t == 1) result.status = no_pairs(T_initial);
      break;
    }
    const Eigen::Isometry3d T_start = T_next;
    T = T_next;
    const LMSummary inner = solve(&run, coarse, &T);
    result.lm_iterations += inner.iterations;
    result.lm_successful_steps += inner.successful_steps;
    if (t == 1) result.initial_cost = run.frame.area(inner.initial_cost);
    result.final_cost = run.frame.area(inner.final_cost);
    result.T_target_source = run.frame.external(T);
    result.iterations = t;
    // The criterion (Sec. 3.2), then the EM scale's M-step at the final pose:
    // s^2 = sum w r / (3 N) = 2 final_cost / (3 N).
    const double scale_sq = run.scale.scale_sq();
    reason = inner.termination == LMTermination::kNumericalFailure
                 ? StopReason::kNumericalFailure
                 : run.monitor.update(
                       IterationReport{t, inner, T, run.reference_length, run.scale.settling()});
    run.scale.update(run.monitor.last_cost_drop(), std::sqrt(run.monitor.last_mse_prev()),
                     2.0 * inner.final_cost / (3.0 * static_cast<double>(pairs.matched)));
    if (options.record_history || options.on_iteration) {
      const IterationRecord r =
          record(t, coarse, scale_sq, inner, run, result.T_target_source, start);
      if (options.on_iteration && !options.on_iteration(r) && reason == StopReason::kNone) {
        reason = StopReason::kCancelled;
      }
      if (options.record_history) result.history.push_back(r);
    }
    // Where the next iteration starts (pose_acceleration.hpp): extrapolated through the coarse
    // phase, where the held scale makes every iteration the same map of the pose; not in the fine
    // phase, where it drew lidar scans toward the cost's optimum, farther from the truth.
    const bool extrapolate = reason == StopReason::kNone && coarse && run.scale.coarse();
    T_next = extrapolate ? run.acceleration.next(T_start, T) : T;
    if (!extrapolate) run.acceleration.reset();
  }
  summarise(reason, T, run, &result);
  set_verdict(&result);
  return result;
}

IterationRecord Registration::Impl::record(int t, bool coarse, double scale_sq,
                                           const LMSummary& summary, const Run& run,
                                           const Eigen::Isometry3d& T_target_source,
                                           Clock::time_point start) const {
  IterationRecord r;
  r.iteration = t;
  r.coarse = coarse;
  r.successful_steps = summary.successful_steps;
  r.unsuccessful_steps = summary.unsuccessful_steps;
  r.initial_cost = run.frame.area(summary.initial_cost);
  r.final_cost = run.frame.area(summary.final_cost);
  r.cost_drop = run.monitor.last_cost_drop();
  r.mse_prev = run.frame.area(run.monitor.last_mse_prev());
  r.scale = run.frame.length(std::sqrt(scale_sq));
  r.correspondences = associator.table().all_pairs();
  r.matched_source_points = associator.table().all_matched();
  r.T_target_source = T_target_source;
  r.time_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return r;
}

// The information and the covariance at the final pose, the measures of agreement and, with
// the plane model, the directions the target's surfaces leave free (judged on the target's
// normals also with source normals: the null directions are the surfaces', whatever normal the
// pairs use).
void Registration::Impl::summarise(StopReason reason, const Eigen::Isometry3d& T, const Run& run,
                                   RegistrationResult* result) {
  if (reason == StopReason::kNumericalFailure) {
    result->status =
        Status(StatusCode::kNumericalFailure,
               "non-finite cost or step in outer iteration " + std::to_string(result->iterations));
  }
  result->stop_reason = reason;
  result->scale = run.frame.length(std::sqrt(run.scale.scale_sq()));
  if (result->iterations == 0) return;
  result->information = run.frame.information(lm.last().H);
  const Clock::time_point start = Clock::now();
  // On the target's surface: within 2 spacings of it; with the plane model, of the nearest
  // target point's tangent plane, that point within the target's median normal-fit reach.
  const bool planes = plane_model();
  const double spacing = target_fits.spacing;
  const detail::SurfaceTest surface{kCloseSpacings * spacing,
                                    planes ? &target_plane_points : nullptr, target_fits.reach};
  const detail::AlignmentQuality q = detail::measure_alignment(
      tree, target.centered, source.centered, pair_normals() ? &source_tree : nullptr, T,
      solver.radius, std::min(solver.radius, kNearSpacings * spacing), surface, &parallel,
      &quality_scratch);
  result->fitness = q.fitness;
  result->inlier_rmse = run.frame.length(q.inlier_rmse);
  result->overlap = q.overlap;
  // Without a spacing (a target of duplicated points) there is no surface to be close to.
  result->close_fraction =
      spacing > 0.0 ? q.close_fraction : std::numeric_limits<double>::quiet_NaN();
  detail::Matrix6d H_normal;
  if (planes) {
    H_normal = detail::NormalEquations::normal_information(
        associator.points(), associator.table(), T, lm.weights().data(), target_plane_points,
        &parallel, &information_blocks);
    result->degenerate_directions = detail::degenerate_directions(H_normal, run.source_rms);
  }
  result->covariance = run.frame.covariance(covariance(T, run, planes ? &H_normal : nullptr));
  result->quality_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The pose's covariance in the internal frame (covariance.hpp): the sandwich over the source's
// patches, or with fewer than kMinClusters of them the residuals' s^2 H_GN in its middle; with the
// plane model released along the free directions of H_normal. With no pair left (nothing
// measured the pose) every direction gets the radius, as a free one.
detail::Matrix6d Registration::Impl::covariance(const Eigen::Isometry3d& T, const Run& run,
                                                const detail::Matrix6d* H_normal) {
  const detail::WeightParams& e_step = run.problem.weights;
  const detail::GradientTerms terms{&associator.points(),
                                    &associator.table(),
                                    lm.weights().data(),
                                    T,
                                    &target.centered,
                                    plane_model() ? &plane : nullptr,
                                    e_step};
  const detail::CovarianceSums sums =
      detail::covariance_sums(terms, &parallel, &covariance_clusters);
  const detail::Matrix6d& H_gn = lm.last().H;
  const detail::Matrix6d H_true = H_gn - e_step.inv_scale_sq * sums.curvature;
  const detail::Matrix6d meat =
      sums.clusters >= detail::kMinClusters ? sums.meat : (1.0 / e_step.inv_scale_sq) * H_gn;
  detail::Matrix6d C = detail::sandwich_covariance(H_true, meat);
  if (sums.clusters == 0 || !(H_true.diagonal().maxCoeff() > 0.0) || !C.allFinite()) {
    C = detail::Matrix6d::Zero();
    const double reach = solver.radius, rotation = solver.radius / run.source_rms;
    C.diagonal() << rotation * rotation, rotation * rotation, rotation * rotation, reach * reach,
        reach * reach, reach * reach;
    return C;
  }
  if (H_normal == nullptr) return C;
  return detail::release_free_directions(C, *H_normal, run.source_rms, solver.radius);
}

RegistrationResult align(const PointCloud& source, const PointCloud& target,
                         const RegistrationOptions& options, const Eigen::Isometry3d& T_initial) {
  Registration registration(options);
  Status s = registration.set_target(target);
  if (!s.ok()) return refused(s, T_initial, RegistrationResult());
  return registration.align(source, T_initial);
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
