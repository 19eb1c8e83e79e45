// degeneracy.hpp - the directions of motion a target's surfaces leave unconstrained.
#pragma once

#include "model/normal_equations.hpp"
#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// Counts the eigenvalues of the surface-normal information H_normal
/// (NormalEquations::normal_information), with its rotation block scaled by rms_radius^2 so both
/// blocks are in cloud units^2, below kDegenerateRatio of the largest; -1 when H_normal is not
/// finite or zero. Measured ratios (identical clouds moved by 0.02 rad / 1.5 cm): the free
/// directions of a plane 0, of a cylinder and a sphere 2.7e-4 to 3.5e-4 (PCA normals of sampled
/// curved surfaces are not exact); the smallest constrained one 0.098-0.26 on the bunny, the
/// lidar pair and a cylinder. 1e-2 lies 30x and 10x from both.
int degenerate_directions(const Matrix6d& H_normal, double rms_radius);

constexpr double kDegenerateRatio = 1e-2;

/// Releases covariance C (of a twist (omega, v), about the same point as H_normal) along the
/// directions degenerate_directions() counts: C's part in the other directions is kept, and
/// along the free ones it is a standard deviation of `reach` (a length; rotations: reach /
/// rms_radius): the pose is known there only to within the association's reach. Returns C
/// unchanged when there is none.
Matrix6d release_free_directions(const Matrix6d& C, const Matrix6d& H_normal, double rms_radius,
                                 double reach);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
