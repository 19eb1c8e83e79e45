// Tests of detail::direction_sector and detail::on_boundary (boundary.hpp) against a reference
// that takes each direction's sector from atan2 and walks the circle for empty sectors, and of
// compute_normals' boundary flags on a sampled patch whose edge is known.
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "association/kdtree.hpp"
#include "core_test_util.hpp"
#include "preparation/boundary.hpp"
#include "preparation/pca_normals.hpp"

using core_test::Rng;
using ppcr::PointCloud;
using ppcr::detail::on_boundary;

namespace {

constexpr double kSectorWidth = M_PI / 8.0;  // 22.5 degrees

// The direction's angle counter-clockwise from the a axis, in [0, 2 pi), by atan2.
double angle_of(double a, double b) {
  const double t = std::atan2(b, a);
  return t < 0.0 ? t + 2.0 * M_PI : t;
}

// Whether the angle lies within 1e-9 of a sector's edge, where rounding decides.
bool near_edge(double angle) {
  const double f = angle / kSectorWidth;
  return std::abs(f - std::round(f)) < 1e-9;
}

// The reference: each direction's sector from atan2, then the longest circular run of empty
// sectors by walking the circle; no direction: not a boundary point.
struct Reference {
  bool decided = true;  // no direction within 1e-9 of a sector's edge
  bool boundary = false;
};
Reference reference(const PointCloud& points, const Eigen::Vector3d& y, const Eigen::Vector3d& n) {
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  bool occupied[16] = {};
  Reference ref;
  bool any = false;
  for (const Eigen::Vector3d& p : points) {
    const double a = (p - y).dot(u), b = (p - y).dot(v);
    if (a == 0.0 && b == 0.0) continue;
    const double angle = angle_of(a, b);
    if (near_edge(angle)) ref.decided = false;
    occupied[static_cast<int>(angle / kSectorWidth) % 16] = true;
    any = true;
  }
  int longest = 0;
  for (int start = 0; start < 16; ++start) {
    int run = 0;
    while (run < 16 && !occupied[(start + run) % 16]) ++run;
    longest = std::max(longest, run);
  }
  ref.boundary = any && longest >= ppcr::detail::kBoundarySectors;
  return ref;
}

std::vector<std::uint32_t> all_of(const PointCloud& points) {
  std::vector<std::uint32_t> idx(points.size());
  std::iota(idx.begin(), idx.end(), 0u);
  return idx;
}

}  // namespace

TEST_CASE("direction_sector: atan2's sector of 22.5 degrees, every direction", "[boundary]") {
  Rng rng(400);
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    const double angle = core_test::uniform(rng, 0.0, 2.0 * M_PI);
    const double r = std::exp(core_test::uniform(rng, -20.0, 20.0));
    const double a = r * std::cos(angle), b = r * std::sin(angle);
    const double exact = angle_of(a, b);
    if (near_edge(exact)) continue;
    INFO("a " << a << ", b " << b << ", angle " << exact);
    REQUIRE(ppcr::detail::direction_sector(a, b) == static_cast<int>(exact / kSectorWidth) % 16);
    ++checked;
  }
  CHECK(checked > 199000);
  // The axes start their sectors, exactly.
  CHECK(ppcr::detail::direction_sector(1.0, 0.0) == 0);
  CHECK(ppcr::detail::direction_sector(0.0, 2.0) == 4);
  CHECK(ppcr::detail::direction_sector(-3.0, 0.0) == 8);
  CHECK(ppcr::detail::direction_sector(0.0, -0.5) == 12);
  // Just inside the first and last sectors, and either side of the half turn.
  CHECK(ppcr::detail::direction_sector(1.0, 1e-300) == 0);
  CHECK(ppcr::detail::direction_sector(1.0, -1e-300) == 15);
  CHECK(ppcr::detail::direction_sector(-1.0, 1e-300) == 7);
  CHECK(ppcr::detail::direction_sector(-1.0, -1e-300) == 8);
}

TEST_CASE("on_boundary: the empty sectors against atan2's, over random neighbourhoods",
          "[boundary]") {
  Rng rng(401);
  int decided = 0, flagged = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Eigen::Vector3d n = core_test::random_unit_vector(rng);
    const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
    const Eigen::Vector3d y(core_test::uniform(rng, -5, 5), core_test::uniform(rng, -5, 5),
                            core_test::uniform(rng, -5, 5));
    // Directions within a random arc (so that every gap size occurs), off the plane by a little
    // (a plane fit's neighbours are not on its plane), at random distances.
    const int count = 1 + static_cast<int>(core_test::uniform(rng, 0, 40));
    const double arc = core_test::uniform(rng, 0.5, 2.0 * M_PI);
    const double start = core_test::uniform(rng, -M_PI, M_PI);
    PointCloud points;
    for (int i = 0; i < count; ++i) {
      const double a = start + core_test::uniform(rng, 0, arc);
      const double r = core_test::uniform(rng, 0.01, 2.0);
      points.push_back(y + r * (std::cos(a) * u + std::sin(a) * v) +
                       core_test::uniform(rng, -0.1, 0.1) * n);
    }
    const std::vector<std::uint32_t> idx = all_of(points);
    const Reference ref = reference(points, y, n);
    if (!ref.decided) continue;
    INFO("trial " << trial << ", " << count << " points");
    CHECK(on_boundary(points, y, n, idx.data(), count) == ref.boundary);
    ++decided;
    flagged += ref.boundary;
  }
  // Both answers are exercised.
  CHECK(decided > 19000);
  CHECK(flagged > decided / 5);
  CHECK(flagged < decided * 4 / 5);
}

TEST_CASE("on_boundary: one direction, none, and no normal", "[boundary]") {
  const Eigen::Vector3d y(1, 2, 3), n = Eigen::Vector3d::UnitZ();
  // Two points along one ray: a full turn is empty.
  const PointCloud ray = {y + Eigen::Vector3d(1, 0, 0), y + Eigen::Vector3d(2, 0, 0.1)};
  const std::vector<std::uint32_t> idx = {0, 1};
  CHECK(on_boundary(ray, y, n, idx.data(), 2));
  CHECK(on_boundary(ray, y, n, idx.data(), 1));
  // Neighbours on y itself, or along its normal, give no direction; a zero normal, no plane.
  const PointCloud on_y = {y, y + Eigen::Vector3d(0, 0, 0.5)};
  CHECK_FALSE(on_boundary(on_y, y, n, idx.data(), 2));
  CHECK_FALSE(on_boundary(ray, y, Eigen::Vector3d::Zero(), idx.data(), 2));
  // Two opposite directions leave two half turns: 7 empty sectors each.
  const PointCloud opposite = {y + Eigen::Vector3d(1, 0, 0), y - Eigen::Vector3d(3, 0, 0)};
  CHECK(on_boundary(opposite, y, n, idx.data(), 2));
  // Four at right angles: 3 empty sectors between each two.
  const PointCloud cross = {y + Eigen::Vector3d(1, 0, 0), y + Eigen::Vector3d(0, 1, 0),
                            y - Eigen::Vector3d(1, 0, 0), y - Eigen::Vector3d(0, 2, 0)};
  const std::vector<std::uint32_t> four = {0, 1, 2, 3};
  CHECK_FALSE(on_boundary(cross, y, n, four.data(), 4));
  CHECK(on_boundary(cross, y, n, four.data(), 3));  // a half turn empty
}

TEST_CASE("compute_normals flags a sampled patch's edge and not its interior", "[boundary]") {
  // A tilted, gently curved 41 x 41 grid with spacing 0.01, jittered by up to a tenth of it: its
  // outermost ring of points lies on the boundary, the points 4 spacings or more inside do not.
  Rng rng(402);
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  PointCloud patch;
  std::vector<double> edge_distance;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 40; ++j) {
      const double a = 0.01 * i + core_test::uniform(rng, -0.001, 0.001);
      const double b = 0.01 * j + core_test::uniform(rng, -0.001, 0.001);
      patch.push_back(a * u + b * v + 0.2 * (a * a - b * b) * n);
      edge_distance.push_back(0.01 * std::min(std::min(i, 40 - i), std::min(j, 40 - j)));
    }
  }
  ppcr::detail::KdTree tree;
  REQUIRE(tree.build(patch).ok());
  for (int threads : {1, 2}) {
    std::vector<Eigen::Vector3d> normals;
    ppcr::detail::Buffer<std::uint8_t> boundary;
    ppcr::detail::compute_normals(patch, tree, 20, core_test::parallel(threads), &normals, nullptr,
                                  nullptr, nullptr, &boundary);
    REQUIRE(boundary.size() == patch.size());
    int edge = 0, interior = 0;
    for (std::size_t i = 0; i < patch.size(); ++i) {
      INFO("point " << i << " at " << edge_distance[i] << " from the edge");
      if (edge_distance[i] < 0.005) {
        CHECK(boundary[i] == 1);
        ++edge;
      } else if (edge_distance[i] > 0.035) {
        CHECK(boundary[i] == 0);
        ++interior;
      }
    }
    CHECK(edge == 160);
    CHECK(interior > 1000);
  }
}
