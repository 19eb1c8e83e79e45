// verdict.hpp - the quality verdict on a finished registration (RegistrationResult::quality):
// good, weak or failed, with the reason, from the measures of agreement computed after the loop.
//
// Rules, in order (the first that fires gives the reason; docs/BENCHMARK.md, "The verdict", has
// the measurements they were chosen on and how well they separate right from wrong results):
//   failed: the status is not ok (refused input, no correspondence, numerical failure); fitness
//           below kFailedFitness; close_fraction below kFailedClose (a NaN close_fraction, a
//           target without a spacing, skips the close_fraction rules).
//   weak:   close_fraction below kWeakClose; fitness below kWeakFitness; degenerate directions
//           with close_fraction below kDegenerateClose (free directions alone flag many right
//           results, so they count only with a loose fit); the iteration cap, or a cancel.
#pragma once

#include "ppcr/abi.hpp"
#include "ppcr/result.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

constexpr double kFailedFitness = 0.05;
constexpr double kFailedClose = 0.6;
constexpr double kWeakClose = 0.75;
constexpr double kWeakFitness = 0.5;
constexpr double kDegenerateClose = 0.9;

// The thresholds' values are also spelled out in judge()'s reasons.
struct Verdict {
  Quality quality = Quality::kFailed;
  const char* reason = "";  // static text; empty for kGood
};

/// The verdict on r, from its status, stop reason, fitness, close_fraction and
/// degenerate_directions.
Verdict judge(const RegistrationResult& r);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
