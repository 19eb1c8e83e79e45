// scene.cpp - casting a ray into the union of a scene's primitives; scene bounds.
#include "scene.hpp"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

// The first surface met by a ray in a union of solids and surfaces is the nearest of the first
// hits of the ray with each primitive; the hierarchy skips the primitives whose bounding box the
// ray misses or meets only beyond the best hit so far.
double Scene::cast(const Ray& ray, double t_max) const {
  return bvh.nearest(ray, t_max, [this, &ray](const PrimitiveRef& ref, double t_best) {
    switch (ref.kind) {
      case PrimitiveKind::kRectangle:
        return intersect(ray, rectangles[ref.index], 0.0, t_best);
      case PrimitiveKind::kBox:
        return intersect(ray, boxes[ref.index], 0.0, t_best);
      case PrimitiveKind::kSphere:
        return intersect(ray, spheres[ref.index], 0.0, t_best);
      case PrimitiveKind::kCylinder:
        return intersect(ray, cylinders[ref.index], 0.0, t_best);
    }
    return kNoHit;
  });
}

void Scene::finalize() {
  std::vector<PrimitiveRef> refs;
  std::vector<Eigen::AlignedBox3d> extents;
  auto add = [&](PrimitiveKind kind, std::size_t index, const Eigen::AlignedBox3d& box) {
    refs.push_back({kind, static_cast<std::uint32_t>(index)});
    extents.push_back(box);
  };
  for (std::size_t i = 0; i < rectangles.size(); ++i) {
    add(PrimitiveKind::kRectangle, i, bounding_box(rectangles[i]));
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    add(PrimitiveKind::kBox, i, bounding_box(boxes[i]));
  }
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    add(PrimitiveKind::kSphere, i, bounding_box(spheres[i]));
  }
  for (std::size_t i = 0; i < cylinders.size(); ++i) {
    add(PrimitiveKind::kCylinder, i, bounding_box(cylinders[i]));
  }
  bounds.setEmpty();
  for (Eigen::AlignedBox3d& box : extents) {
    bounds.extend(box);
    // Padding: a flat rectangle's box has zero thickness, and a ray grazing a box's face must
    // not be culled by rounding in the slab test.
    box.min().array() -= 1e-6;
    box.max().array() += 1e-6;
  }
  bvh.build(std::move(refs), std::move(extents));
}

Scene make_scene(SceneKind kind, std::uint64_t seed) {
  switch (kind) {
    case SceneKind::kStreet:
      return make_street(seed);
    case SceneKind::kObjects:
      return make_objects(seed);
    case SceneKind::kRoom:
      break;
  }
  return make_room(seed);
}

}  // namespace internal

const char* to_string(SceneKind kind) {
  switch (kind) {
    case SceneKind::kRoom:
      return "room";
    case SceneKind::kStreet:
      return "street";
    case SceneKind::kObjects:
      return "objects";
  }
  return "unknown";
}

double max_translation_m(SceneKind kind) {
  switch (kind) {
    case SceneKind::kStreet:
      return internal::kStreetMaxTranslation;
    case SceneKind::kObjects:
      return internal::kObjectsMaxTranslation;
    case SceneKind::kRoom:
      break;
  }
  return internal::kRoomMaxTranslation;
}

}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
