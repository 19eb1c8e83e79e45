// pair_normal_reference.hpp - an independent reference for the plane model's pair normals
// (pair_normals.hpp): of n + R m and n - R m, the longer one, normalised (|n +- R m|^2 =
// 2 +- 2 n . R m, so the longer one is the sum with the source normal on the target's side),
// instead of choosing the sign by the dot product.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "association/association_table.hpp"

namespace core_test {

/// The pair normal of target normal n and source normal m at rotation R: zero without a target
/// normal, n without a source normal.
inline Eigen::Vector3d reference_pair_normal(const Eigen::Vector3d& n, const Eigen::Vector3d& m,
                                             const Eigen::Matrix3d& R) {
  if (n.squaredNorm() == 0.0) return Eigen::Vector3d::Zero();
  if (m.squaredNorm() == 0.0) return n;
  const Eigen::Vector3d plus = n + R * m, minus = n - R * m;
  return plus.norm() >= minus.norm() ? plus.normalized() : minus.normalized();
}

/// Per association slot j*k+q (zero past a row's count), the pair normal of its target point's
/// normal and source point j's.
inline std::vector<Eigen::Vector3d> reference_pair_normals(
    const ppcr::detail::AssociationTable& assoc, const std::vector<Eigen::Vector3d>& target_normals,
    const std::vector<Eigen::Vector3d>& source_normals, const Eigen::Matrix3d& R) {
  const std::size_t k = static_cast<std::size_t>(assoc.k);
  std::vector<Eigen::Vector3d> out(assoc.index.size(), Eigen::Vector3d::Zero());
  for (std::size_t j = 0; j < assoc.count.size(); ++j) {
    for (std::size_t q = 0; q < assoc.count[j]; ++q) {
      const std::size_t slot = j * k + q;
      out[slot] = reference_pair_normal(target_normals[assoc.index[slot]], source_normals[j], R);
    }
  }
  return out;
}

}  // namespace core_test
