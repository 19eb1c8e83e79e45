// overlap.cpp - k-nearest-neighbour queries (nanoflann) for spacing and overlap.
#include "overlap.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <nanoflann.hpp>
#include <vector>

namespace ppcr_synth {
namespace {

struct CloudAdaptor {
  const ppcr::PointCloud& cloud;
  std::size_t kdtree_get_point_count() const { return cloud.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return cloud[i][static_cast<Eigen::Index>(dim)];
  }
  template <typename Box>
  bool kdtree_get_bbox(Box& /*box*/) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CloudAdaptor>,
                                                 CloudAdaptor, 3, std::uint32_t>;

}  // namespace

double scan_spacing(const ppcr::PointCloud& cloud) {
  constexpr std::size_t kNeighbour = 8;
  if (cloud.size() <= kNeighbour) return 0.0;
  const CloudAdaptor adaptor{cloud};
  Tree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  std::vector<double> distances;
  distances.reserve(cloud.size());
  std::uint32_t index[kNeighbour + 1];
  double squared[kNeighbour + 1];
  for (const Eigen::Vector3d& p : cloud) {
    const std::size_t found = tree.knnSearch(p.data(), kNeighbour + 1, index, squared);
    if (found == kNeighbour + 1) distances.push_back(std::sqrt(squared[kNeighbour]));  // [0]: p
  }
  if (distances.empty()) return 0.0;
  const auto middle = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  return *middle;
}

double overlap_fraction(const ppcr::PointCloud& source, const Eigen::Isometry3d& target_T_source,
                        const ppcr::PointCloud& target, double radius) {
  if (source.empty() || target.empty()) return 0.0;
  const CloudAdaptor adaptor{target};
  Tree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  std::size_t covered = 0;
  for (const Eigen::Vector3d& p : source) {
    const Eigen::Vector3d q = target_T_source * p;
    std::uint32_t index = 0;
    double squared = 0.0;
    if (tree.knnSearch(q.data(), 1, &index, &squared) == 1 && squared <= radius * radius) {
      ++covered;
    }
  }
  return static_cast<double>(covered) / static_cast<double>(source.size());
}

}  // namespace ppcr_synth
