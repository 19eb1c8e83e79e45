// bvh.hpp - a bounding volume hierarchy over a scene's primitives, so that a ray is only tested
// against the primitives whose bounding boxes it meets (internal to ppcr_synthetic).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "ppcr/abi.hpp"
#include "primitives.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

enum class PrimitiveKind : std::uint8_t { kRectangle, kBox, kSphere, kCylinder };

/// A primitive of a scene: its kind and its index in the scene's vector of that kind.
struct PrimitiveRef {
  PrimitiveKind kind = PrimitiveKind::kRectangle;
  std::uint32_t index = 0;
};

class Bvh {
 public:
  /// Builds the hierarchy: boxes[i] bounds primitives[i]. Nodes are split at the median of the
  /// primitives' box centres along the axis where the centres spread most; leaves hold at most
  /// four primitives.
  void build(std::vector<PrimitiveRef> primitives, std::vector<Eigen::AlignedBox3d> boxes);

  bool empty() const { return nodes_.empty(); }

  /// The nearest hit in (0, t_max) among the primitives whose box the ray meets, or kNoHit.
  /// hit(ref, t_best) must return the ray's first hit with that primitive below t_best (or
  /// kNoHit). No allocation: the traversal stack is a fixed array (the depth is logarithmic).
  template <typename Hit>
  double nearest(const Ray& ray, double t_max, Hit&& hit) const {
    if (nodes_.empty()) return kNoHit;
    const Eigen::Vector3d inverse = ray.direction.cwiseInverse();
    double best = t_max;
    std::uint32_t stack[kMaxDepth + 1];
    int size = 0;
    stack[size++] = 0;
    while (size > 0) {
      const std::uint32_t at = stack[--size];
      const Node& node = nodes_[at];
      if (!meets(node.box, ray, inverse, best)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
          const double t = hit(primitives_[i], best);
          if (t < best) best = t;
        }
      } else {
        stack[size++] = node.second_child;
        stack[size++] = at + 1;  // the first child follows its parent
      }
    }
    return best < t_max ? best : kNoHit;
  }

 private:
  static constexpr int kMaxDepth = 64;

  struct Node {
    Eigen::AlignedBox3d box;
    std::uint32_t first = 0;         // leaf: first primitive
    std::uint32_t count = 0;         // leaf: number of primitives (0 for an inner node)
    std::uint32_t second_child = 0;  // inner node: index of the second child (the first follows)
  };

  /// Slab test of the ray against the box over t in [0, t_max].
  static bool meets(const Eigen::AlignedBox3d& box, const Ray& ray, const Eigen::Vector3d& inverse,
                    double t_max);
  std::uint32_t build_node(std::size_t first, std::size_t last, int depth);

  std::vector<Node> nodes_;
  std::vector<PrimitiveRef> primitives_;
  std::vector<Eigen::AlignedBox3d> boxes_;  // parallel to primitives_ (used while building)
};

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
