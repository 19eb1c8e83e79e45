// pair_normals.hpp - per-association normals of the plane model with source normals
// (PlaneOptions::source_normals, error_model.hpp).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "association.hpp"
#include "normal_equations.hpp"
#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// For every association slot (j, m) of the table (stride assoc.k), the normal of the pair
/// (target point y = assoc.index[j*k+m] with normal n_k = target_points[y].n, source point j), with
/// R = R_target_source:
///   n_kj = (n_k + s R m_j) / |n_k + s R m_j|,   s = +1 if n_k . R m_j >= 0, else -1,
/// the mean of the two surfaces' normals in the target frame (s flips the source normal onto
/// the target's side: PCA normals have no sign; |n_k + s R m_j| >= sqrt(2), never degenerate).
/// A source point without a normal (m_j = 0) keeps n_k; a target point without one (n_k = 0)
/// keeps 0 (Omega = I). Slots past count[j] are not written. Parallel over source points,
/// allocation-free; pair_normals must hold assoc.index.size() entries.
void compute_pair_normals(const AssociationTable& assoc,
                          const std::vector<PlanePoint>& target_points,
                          const std::vector<Eigen::Vector3d>& source_normals,
                          const Eigen::Matrix3d& R_target_source, int num_threads,
                          std::vector<Eigen::Vector3d>* pair_normals);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
