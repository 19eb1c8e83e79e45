// verdict.cpp - see verdict.hpp.
#include "quality/verdict.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

const char* to_string(Quality quality) {
  switch (quality) {
    case Quality::kGood:
      return "good";
    case Quality::kWeak:
      return "weak";
    case Quality::kFailed:
      return "failed";
  }
  return "unknown";
}

namespace detail {

Verdict judge(const RegistrationResult& r) {
  if (!r.status.ok()) return {Quality::kFailed, "the registration failed (see its status)"};
  if (r.fitness < kFailedFitness) {
    return {Quality::kFailed,
            "fitness below 5 %: almost no source point has a target point within the radius"};
  }
  if (r.close_fraction < kFailedClose) {
    return {Quality::kFailed,
            "fewer than 60 % of the source points near the target lie on its surface: the "
            "surfaces do not coincide"};
  }
  if (r.close_fraction < kWeakClose) {
    return {Quality::kWeak,
            "fewer than 75 % of the source points near the target lie on its surface"};
  }
  if (r.fitness < kWeakFitness) {
    return {Quality::kWeak, "fitness below 50 %: little overlap, or a wrong pose"};
  }
  if (r.degenerate_directions > 0 && r.close_fraction < kDegenerateClose) {
    return {Quality::kWeak,
            "the target's surfaces leave directions free and fewer than 90 % of the source "
            "points near the target lie on its surface"};
  }
  if (r.stop_reason == StopReason::kMaxIterations) {
    return {Quality::kWeak, "the iteration cap stopped the registration before its criterion"};
  }
  if (r.stop_reason == StopReason::kCancelled) {
    return {Quality::kWeak, "cancelled before its criterion stopped it"};
  }
  return {Quality::kGood, ""};
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
