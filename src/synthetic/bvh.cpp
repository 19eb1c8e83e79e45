// bvh.cpp - building the bounding volume hierarchy; ray-box slab test.
#include "bvh.hpp"

#include <numeric>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

void Bvh::build(std::vector<PrimitiveRef> primitives, std::vector<Eigen::AlignedBox3d> boxes) {
  primitives_ = std::move(primitives);
  boxes_ = std::move(boxes);
  nodes_.clear();
  if (!primitives_.empty()) build_node(0, primitives_.size(), 0);
  boxes_.clear();
  boxes_.shrink_to_fit();
}

std::uint32_t Bvh::build_node(std::size_t first, std::size_t last, int depth) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box;
  Eigen::AlignedBox3d centres;
  for (std::size_t i = first; i < last; ++i) {
    box.extend(boxes_[i]);
    centres.extend(boxes_[i].center());
  }
  nodes_[index].box = box;
  const std::size_t count = last - first;
  if (count <= 4 || depth >= kMaxDepth - 1) {
    nodes_[index].first = static_cast<std::uint32_t>(first);
    nodes_[index].count = static_cast<std::uint32_t>(count);
    return index;
  }
  // Median split of the centres along their widest axis (primitives and boxes move together).
  Eigen::Index axis = 0;
  centres.sizes().maxCoeff(&axis);
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), first);
  const std::size_t middle = count / 2;
  std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(middle), order.end(),
                   [&](std::size_t a, std::size_t b) {
                     return boxes_[a].center()[axis] < boxes_[b].center()[axis];
                   });
  std::vector<PrimitiveRef> primitives(count);
  std::vector<Eigen::AlignedBox3d> boxes(count);
  for (std::size_t k = 0; k < count; ++k) {
    primitives[k] = primitives_[order[k]];
    boxes[k] = boxes_[order[k]];
  }
  std::copy(primitives.begin(), primitives.end(),
            primitives_.begin() + static_cast<std::ptrdiff_t>(first));
  std::copy(boxes.begin(), boxes.end(), boxes_.begin() + static_cast<std::ptrdiff_t>(first));
  build_node(first, first + middle, depth + 1);  // the first child follows its parent
  const std::uint32_t second = build_node(first + middle, last, depth + 1);
  nodes_[index].second_child = second;
  return index;
}

// The ray is between the two planes of axis i for t between (min_i - o_i) / d_i and
// (max_i - o_i) / d_i; it meets the box if these three intervals and [0, t_max] intersect. A ray
// parallel to an axis (d_i = 0) is between that pair of planes always or never.
bool Bvh::meets(const Eigen::AlignedBox3d& box, const Ray& ray, const Eigen::Vector3d& inverse,
                double t_max) {
  double t_near = 0.0;
  double t_far = t_max;
  for (int i = 0; i < 3; ++i) {
    if (ray.direction[i] == 0.0) {
      if (ray.origin[i] < box.min()[i] || ray.origin[i] > box.max()[i]) return false;
      continue;
    }
    double t0 = (box.min()[i] - ray.origin[i]) * inverse[i];
    double t1 = (box.max()[i] - ray.origin[i]) * inverse[i];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
    if (t_near > t_far) return false;
  }
  return true;
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
