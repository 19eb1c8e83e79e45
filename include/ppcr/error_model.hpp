// error_model.hpp - how the error of an association is measured.
//
//  kPoint (the paper's): r_kj = |e_kj|^2, e_kj = y_k - T x_j.
//  kPlane (beyond the paper): r_kj = e_kj^T Omega_k e_kj with, for each target point,
//     Omega_k = n_k n_k^T + epsilon I,
//  n_k the unit normal of a plane fitted (PCA) to the target point's normal_neighbours nearest
//  target points. The error along the local surface normal counts fully, the error along the
//  surface by epsilon only, so the registration no longer has to drag points along a surface to
//  their sampled counterparts (the bias and slow creep of point-to-point errors on scans), while
//  epsilon keeps every direction weakly constrained. Target points whose neighbourhood is too
//  small (fewer than 5 points) or not a surface (collinear or identical points: the middle
//  eigenvalue of its covariance below 1e-6 of the largest) keep Omega_k = I. Why n n^T + epsilon I
//  rather than GICP's inverse regularised covariance: the same surface-aligned metric with one
//  scalar to tune, an information matrix that is never singular, and 4 numbers per target point
//  instead of 6. The Mahalanobis r_kj replaces |e_kj|^2 everywhere: in the E-step weights, the
//  cost, the EM scale, the LM normal equations (Omega inside the 6x6 reduction) and the criteria.
//
//  Source normals (PlaneOptions::source_normals, off by default): normals are also fitted to the
//  source (same PCA), and each pair uses the mean of its two surfaces' normals,
//     Omega_kj = n_kj n_kj^T + epsilon I,  n_kj = (n_k + s R m_j) / |n_k + s R m_j|,
//  s = sign(n_k . R m_j) (PCA normals have no sign), R the rotation at the last re-association.
//  Both scans' sampling noise then enters the normal, as GICP's combined covariances C_k + R C_j
//  R^T do, while Omega stays a rank-one-plus-isotropic matrix. n_kj is frozen between
//  re-associations (a constant of the inner LM problem, so the analytic Jacobian stays exact):
//  letting it follow R inside the LM, with a Jacobian that ignores its derivative, made 3 of the
//  50 lidar benchmark problems fail (94 % success). A source point without a normal uses n_k.
//
//  Noise floor (PlaneOptions::noise_floor, off by default): the target's surface noise is the
//  median, over target points with a normal, of the RMS distance of the fit's points from their
//  plane (sqrt of the smallest eigenvalue of the PCA): the sensor's noise and the surfaces'
//  roughness at the fit's scale. The rationale (an explanation, not a measurement): below it,
//  the EM scale makes the weights trust the nearest neighbours' sub-noise offsets. Measured
//  (docs/BENCHMARK.md): 0.22 mm on the bunny and 6.0 cm on the lidar scans; a floor at 1x lowers
//  the lidar median and q0.95 errors by 4-9.5 % and raises the bunny's by 1.5-2.2 %; at 0.8x
//  with dof 1.25 and source normals both sets' medians are below every peer's.
#pragma once

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

enum class ErrorModel {
  kPoint,  // point-to-point (paper eq. 1)
  kPlane,  // plane-aware Mahalanobis error (see above)
};

struct PlaneOptions {
  int normal_neighbours = 20;       // target points in each PCA plane fit (>= 5)
  double epsilon = 0.05;            // in-plane weight of Omega = n n^T + epsilon I (> 0, <= 1)
  bool point_while_coarse = false;  // with the EM scale: point-to-point errors during its coarse
                                    // phase (a wider basin far from the solution), plane after
  bool source_normals = false;      // also fit source normals; pairs use the mean normal (above).
                                    // Costs a source k-d tree per align() (allocates). Like the
                                    // other plane options, ignored by the point model
  double noise_floor = 0.0;         // with the EM scale (weights.hpp): a floor on s of this
                                    // multiple of the target's surface noise
                                    // (RegistrationResult::target_surface_noise), combined with
                                    // WeightOptions::em_min_scale (the larger wins; like it, it
                                    // raises s in the refine phase if above). 0 = off (>= 0).
                                    // "Noise floor" in the file comment. Unused by raw and fixed
                                    // scales
};

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
