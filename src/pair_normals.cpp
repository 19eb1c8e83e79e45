// pair_normals.cpp - per-association normals from target and source normals (see header).
#include "pair_normals.hpp"

#include "parallel.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

void compute_pair_normals(const AssociationTable& assoc,
                          const std::vector<PlanePoint>& target_points,
                          const std::vector<Eigen::Vector3d>& source_normals,
                          const Eigen::Matrix3d& R_target_source, int num_threads,
                          std::vector<Eigen::Vector3d>* pair_normals) {
  const std::size_t k = static_cast<std::size_t>(assoc.k);
  Eigen::Vector3d* out = pair_normals->data();
  parallel_for(num_threads, static_cast<std::ptrdiff_t>(assoc.count.size()), [&](std::ptrdiff_t i) {
    const std::size_t j = static_cast<std::size_t>(i);
    const std::size_t count = assoc.count[j];
    if (count == 0) return;
    const Eigen::Vector3d m = R_target_source * source_normals[j];  // zero stays zero
    const bool has_source_normal = m.squaredNorm() > 0.0;
    for (std::size_t q = 0; q < count; ++q) {
      const std::size_t slot = j * k + q;
      const Eigen::Vector3d& n = target_points[assoc.index[slot]].n;
      if (!has_source_normal || n.squaredNorm() == 0.0) {
        out[slot] = n;
        continue;
      }
      const Eigen::Vector3d sum = n.dot(m) >= 0.0 ? Eigen::Vector3d(n + m) : Eigen::Vector3d(n - m);
      out[slot] = sum / sum.norm();
    }
  });
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
