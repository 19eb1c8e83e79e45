// registration.hpp - register a source cloud onto a target (PPCR, paper Sec. 3).
//
//   ppcr::RegistrationOptions options;
//   options.radius = 0.02;                                   // cloud units
//   ppcr::Registration reg(options);
//   reg.set_target(target);                                  // filters, indexes, fits normals
//   ppcr::RegistrationResult r = reg.align(source, T_guess); // r.T_target_source: source -> target
//
// set_target() and the set-up of align() allocate; the loop itself does not. The core never
// throws across this API and never prints: failures come back in RegistrationResult::status.
#pragma once

#include <Eigen/Geometry>
#include <memory>

#include "ppcr/abi.hpp"
#include "ppcr/options.hpp"
#include "ppcr/result.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

class Registration {
 public:
  explicit Registration(const RegistrationOptions& options = RegistrationOptions());
  ~Registration();
  Registration(Registration&&) noexcept;
  Registration& operator=(Registration&&) noexcept;
  Registration(const Registration&) = delete;
  Registration& operator=(const Registration&) = delete;

  const RegistrationOptions& options() const;

  /// Validates the options, drops non-finite points, voxel-filters and indexes the target, and
  /// fits its normals (plane model). Kept for every align() until the next set_target() or
  /// set_target_to_source(). A refused target leaves none: align() is then refused with the
  /// same status.
  Status set_target(const PointCloud& target);

  /// Makes the source of the last align() the target, as set_target() of the same cloud would,
  /// without filtering, indexing and fitting its normals again: align() has done that for it.
  /// For a sequence, where each scan is the next one's target. Needs source_voxel ==
  /// target_voxel (kInvalidArgument otherwise) and a last align() that got as far as preparing
  /// its source, not taken already (kEmptyCloud otherwise); a refusal leaves no target. The
  /// target keeps the internal unit its points were prepared in (the previous target's) when
  /// that is within 2x of its own: the results then equal set_target()'s to the bit when the
  /// units are the same (a given radius smaller than both clouds' extents), and to rounding
  /// otherwise.
  Status set_target_to_source();

  /// Registers source onto the target set last (refused without one, with the status that
  /// refused the last target). T_initial maps source into the target frame
  /// (the initial guess).
  RegistrationResult align(const PointCloud& source,
                           const Eigen::Isometry3d& T_initial = Eigen::Isometry3d::Identity());

  /// The same, taking the source: its memory is freed (source left empty) once the registration
  /// holds its prepared copy, before the iterations, so that the caller's cloud does not count
  /// in the peak (24 B per point); freed as well when the call is refused.
  RegistrationResult align(PointCloud&& source,
                           const Eigen::Isometry3d& T_initial = Eigen::Isometry3d::Identity());

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience: Registration(options).set_target(target) then align(source, T_initial).
RegistrationResult align(const PointCloud& source, const PointCloud& target,
                         const RegistrationOptions& options = RegistrationOptions(),
                         const Eigen::Isometry3d& T_initial = Eigen::Isometry3d::Identity());

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
