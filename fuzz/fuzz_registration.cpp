// fuzz_registration.cpp - libFuzzer target: ppcr::align on arbitrary small clouds and parameters.
//
// The input is read as (fuzz_registration_input.hpp): a parameter block (radius, k, dof, scale
// mode and scale, error model, criteria, caps, voxel leaves, threads, initial guess), then up to
// 64 source and 64 target points whose coordinates are 16-bit integers times a per-cloud unit
// (2^-40 .. 2^40) plus a per-cloud offset (0 .. 1e300), with reserved codes for NaN, +-Inf,
// +-1e300 and +-DBL_MAX. The target can also be the source moved by a pose (the realistic case).
// Caps are small (<= 12 outer, <= 12 LM iterations) so each run is fast.
//
// Invariants checked on EVERY input (a violation aborts: libFuzzer saves the input):
//  - no exception escapes, no sanitizer report (ASan + UBSan on ppcr too);
//  - the returned pose is finite and rigid (R^T R = I, det R = 1, last row 0 0 0 1), whatever
//    the status: the initial guess is rigid, so a refusal returns it unchanged;
//  - a stop reason is set; 1 <= iterations <= max_iterations unless refused before the loop;
//    the LM total is at most iterations * lm.max_iterations;
//  - history has exactly `iterations` rows when recorded, each with a finite rigid pose, and the
//    last row's pose is the result's;
//  - status ok: the stop reason is not invalid_input / numerical_failure; the final cost and the
//    information matrix are finite; the covariance is finite and symmetric with a non-negative
//    diagonal; degenerate_directions is -1 for the point model and in
//    [0, 6] for the plane model (when the loop ran);
//  - status not ok: the message is not empty;
//  - Registration::align gives ppcr::align's pose; after set_target_to_source() the target
//    registered onto the taken source has a finite rigid pose (a finite cost when ok), and a
//    refused set_target_to_source() leaves no target.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz_registration_input.hpp"
#include "ppcr/registration.hpp"

namespace {

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "fuzz_registration: invariant violated: %s\n", what);
  std::abort();
}

bool rigid(const Eigen::Isometry3d& T) {
  const Eigen::Matrix4d& M = T.matrix();
  if (!M.allFinite()) return false;
  if (M.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) return false;
  const Eigen::Matrix3d R = T.linear();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9) return false;
  return std::abs(R.determinant() - 1.0) < 1e-9;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ppcr_fuzz::RegistrationInput in = ppcr_fuzz::decode_registration_input(data, size);
  const ppcr::RegistrationOptions& o = in.options;
  const ppcr::RegistrationResult r = ppcr::align(in.source, in.target, o, in.T_initial);

  if (!rigid(r.T_target_source)) fail("pose not finite or not rigid");
  if (r.stop_reason == ppcr::StopReason::kNone) fail("no stop reason");
  const bool refused = r.stop_reason == ppcr::StopReason::kInvalidInput;
  if (refused) {
    if (r.status.ok()) fail("invalid_input with an ok status");
    if (r.iterations != 0) fail("refused input but iterations ran");
  } else {
    if (r.iterations < 1 && r.stop_reason != ppcr::StopReason::kNoCorrespondences) {
      fail("the loop stopped before the first iteration without a reason");
    }
  }
  if (r.iterations > o.max_iterations) fail("iterations above max_iterations");
  if (r.lm_iterations < 0 || r.lm_iterations > r.iterations * o.expert.lm_max_iterations) {
    fail("LM iterations above iterations * lm.max_iterations");
  }
  if (r.lm_successful_steps > r.lm_iterations) fail("more successful LM steps than LM steps");
  if (o.record_history) {
    if (static_cast<int>(r.history.size()) != r.iterations) fail("history size != iterations");
    for (const ppcr::IterationRecord& h : r.history) {
      if (!rigid(h.T_target_source)) fail("history pose not finite or not rigid");
      if (h.successful_steps + h.unsuccessful_steps > o.expert.lm_max_iterations) {
        fail("history row above lm.max_iterations");
      }
    }
    if (!r.history.empty() &&
        r.history.back().T_target_source.matrix() != r.T_target_source.matrix()) {
      fail("last history pose != result pose");
    }
  } else if (!r.history.empty()) {
    fail("history recorded although record_history = false");
  }
  if (r.status.ok()) {
    if (r.stop_reason == ppcr::StopReason::kNumericalFailure) fail("numerical_failure but ok");
    if (!std::isfinite(r.final_cost)) fail("ok status with a non-finite final cost");
    if (!r.information.allFinite()) fail("ok status with a non-finite information matrix");
    if (!r.covariance.allFinite() || r.covariance != r.covariance.transpose() ||
        r.covariance.diagonal().minCoeff() < 0.0) {
      fail(
          "ok status with a covariance that is not finite and symmetric with a non-negative "
          "diagonal");
    }
    if (o.error_model == ppcr::ErrorModel::kPoint && r.degenerate_directions != -1) {
      fail("point model reported degenerate directions");
    }
    if (r.degenerate_directions < -1 || r.degenerate_directions > 6) {
      fail("degenerate_directions out of [-1, 6]");
    }
  } else if (r.status.message().empty()) {
    fail("failure without a message");
  }

  // The same source made the target (set_target_to_source), the target registered onto it: the
  // same invariants on the pose and the status, and a refusal leaves no target.
  ppcr::Registration reg(o);
  if (reg.set_target(in.target).ok()) {
    const ppcr::RegistrationResult first = reg.align(in.source, in.T_initial);
    if (first.T_target_source.matrix() != r.T_target_source.matrix()) {
      fail("Registration::align differs from ppcr::align");
    }
    const ppcr::Status s = reg.set_target_to_source();
    const Eigen::Isometry3d back =
        in.T_initial.matrix().allFinite() ? in.T_initial.inverse() : Eigen::Isometry3d::Identity();
    const ppcr::RegistrationResult second = reg.align(in.target, back);
    if (!rigid(second.T_target_source)) fail("pose onto the taken source not rigid");
    if (!s.ok() && (second.status.ok() || s.message().empty())) {
      fail("set_target_to_source refused, yet align ran or no message");
    }
    if (second.status.ok() && !std::isfinite(second.final_cost)) {
      fail("ok status onto the taken source with a non-finite final cost");
    }
    if (!second.status.ok() && second.status.message().empty()) fail("failure without a message");
  }
  return 0;
}
