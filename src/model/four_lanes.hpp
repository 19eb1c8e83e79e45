// four_lanes.hpp - the E-step's Student-t ratios and powers four neighbours at a time, on x86-64
// CPUs with AVX, chosen at run time (the default build targets plain x86-64; a build for AVX,
// e.g. -march=haswell, takes them without asking the CPU).
//
// Each lane runs the two-lane kernel's operations (e_step_kernel.hpp, PowerDyadic) in the same
// order: a division, square roots and products, each correctly rounded (IEEE 754) whatever the
// vector width, none contracted into a fused multiply-add (-ffp-contract=off). So the weights and
// their sum are the same to the bit as the two-lane kernel's (tests/core/test_weights.cpp), and a
// registration's result does not depend on the CPU. Why: the roots of dof 1.25 (three per
// neighbour) are most of the E-step's time, and four lanes of a root cost about what two do
// (docs/PERFORMANCE.md, "Four-lane E-step").
#pragma once

#include <cstddef>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// True when four_lane_dyadic() runs on this CPU: a GCC or Clang build for x86-64, on a CPU (and
/// an operating system) with AVX.
bool four_lanes_available();

/// For the first n rounded down to 4 neighbours, four at a time:
///   q = nu_z_min / (dof + r_sq[k] * inv_scale_sq),  p = q^whole * q^(eighths / 8) (PowerDyadic),
///   *sum += p (lane by lane, in the neighbours' order),  u[k] = p * q.
/// Returns the number of neighbours done. Only when four_lanes_available().
std::size_t four_lane_dyadic(int whole, int eighths, double nu_z_min, double dof,
                             double inv_scale_sq, const double* r_sq, std::size_t n, double* u,
                             double* sum);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
