// Tests of ppcr::voxel_downsample against a brute-force grouping of the points by voxel
// (std::map of floor((p - min) / leaf) -> points), in order of first appearance.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "core_test_util.hpp"
#include "ppcr/voxel.hpp"
#include "preparation/automatic_voxel.hpp"

using core_test::Rng;
using ppcr::PointCloud;

namespace {

PointCloud brute_force(const PointCloud& cloud, double leaf) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  for (const Eigen::Vector3d& p : cloud) {
    if (p.allFinite()) lo = lo.cwiseMin(p);
  }
  struct Group {
    std::size_t first;
    Eigen::Vector3d sum;
    std::size_t count;
  };
  std::map<std::array<long long, 3>, Group> groups;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d& p = cloud[i];
    if (!p.allFinite()) continue;
    std::array<long long, 3> key;
    for (int a = 0; a < 3; ++a)
      key[static_cast<std::size_t>(a)] = static_cast<long long>(std::floor((p[a] - lo[a]) / leaf));
    auto it = groups.find(key);
    if (it == groups.end()) {
      groups.emplace(key, Group{i, p, 1});
    } else {
      it->second.sum += p;
      ++it->second.count;
    }
  }
  std::vector<Group> ordered;
  for (const auto& kv : groups) ordered.push_back(kv.second);
  std::sort(ordered.begin(), ordered.end(),
            [](const Group& a, const Group& b) { return a.first < b.first; });
  PointCloud out;
  for (const Group& g : ordered) out.push_back(g.sum / static_cast<double>(g.count));
  return out;
}

double max_diff(const PointCloud& a, const PointCloud& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, (a[i] - b[i]).cwiseAbs().maxCoeff());
  return m;
}

}  // namespace

TEST_CASE("voxel_downsample equals brute-force grouping, in order of first appearance", "[voxel]") {
  Rng rng(91);
  PointCloud uniform = core_test::uniform_cloud(rng, 20000, -3.0, 2.0);
  PointCloud scene = core_test::analytic_scene(rng, 20000);
  PointCloud offset = core_test::uniform_cloud(rng, 5000, -1.0, 1.0);
  for (Eigen::Vector3d& p : offset) p += Eigen::Vector3d(1e5, -2e5, 3e4);
  for (const PointCloud* cloud : {&uniform, &scene, &offset}) {
    for (double leaf : {0.013, 0.1, 0.37, 1.0, 10.0}) {
      PointCloud out;
      REQUIRE(ppcr::voxel_downsample(*cloud, leaf, &out).ok());
      const PointCloud ref = brute_force(*cloud, leaf);
      INFO("leaf " << leaf << " points " << cloud->size());
      REQUIRE(out.size() == ref.size());
      CHECK(max_diff(out, ref) <= 1e-12 * (1.0 + (*cloud)[0].norm()));
    }
  }
}

TEST_CASE("voxel_downsample: points on voxel boundaries go to the upper voxel", "[voxel]") {
  // Power-of-two leaf and coordinates: (p - min) / leaf is exact.
  const PointCloud cloud = {Eigen::Vector3d(0, 0, 0),     Eigen::Vector3d(0.25, 0, 0),
                            Eigen::Vector3d(0.125, 0, 0), Eigen::Vector3d(0.5, 0, 0),
                            Eigen::Vector3d(0.375, 0, 0), Eigen::Vector3d(0.25, 0.25, 0)};
  PointCloud out;
  REQUIRE(ppcr::voxel_downsample(cloud, 0.25, &out).ok());
  const PointCloud expected = {Eigen::Vector3d(0.0625, 0, 0), Eigen::Vector3d(0.3125, 0, 0),
                               Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0.25, 0.25, 0)};
  REQUIRE(out.size() == expected.size());
  for (std::size_t i = 0; i < out.size(); ++i) CHECK(out[i] == expected[i]);
  CHECK(brute_force(cloud, 0.25) == expected);
}

TEST_CASE("voxel_downsample skips non-finite points", "[voxel]") {
  Rng rng(92);
  PointCloud cloud = core_test::uniform_cloud(rng, 3000, 0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  PointCloud dirty = cloud;
  dirty.insert(dirty.begin(), Eigen::Vector3d(nan, 0.5, 0.5));
  dirty.insert(dirty.begin() + 100, Eigen::Vector3d(-inf, -inf, -inf));  // would move the min
  dirty.push_back(Eigen::Vector3d(0.5, inf, 0.5));
  dirty.push_back(Eigen::Vector3d(nan, nan, nan));
  PointCloud out_dirty, out_clean;
  REQUIRE(ppcr::voxel_downsample(dirty, 0.1, &out_dirty).ok());
  REQUIRE(ppcr::voxel_downsample(cloud, 0.1, &out_clean).ok());
  CHECK(out_dirty == out_clean);
  for (const Eigen::Vector3d& p : out_dirty) CHECK(p.allFinite());
  // Only non-finite points: an empty output, not an error.
  PointCloud out;
  CHECK(ppcr::voxel_downsample({Eigen::Vector3d(nan, 0, 0)}, 0.1, &out).ok());
  CHECK(out.empty());
  CHECK(ppcr::voxel_downsample(PointCloud(), 0.1, &out).ok());
  CHECK(out.empty());
}

TEST_CASE("voxel_downsample: leaf <= 0 or non-finite is refused", "[voxel]") {
  const PointCloud cloud = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)};
  for (double leaf :
       {0.0, -0.1, -std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    PointCloud out = {Eigen::Vector3d(7, 7, 7)};
    const ppcr::Status s = ppcr::voxel_downsample(cloud, leaf, &out);
    INFO("leaf " << leaf << ": " << s.to_string());
    CHECK(s.code() == ppcr::StatusCode::kInvalidArgument);
    CHECK(s.message().find("leaf") != std::string::npos);
  }
}

TEST_CASE("voxel_downsample: a leaf too small for the extent is refused", "[voxel]") {
  const PointCloud cloud = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1)};
  PointCloud out;
  // 2^21 + 1 cells along z: refused, the message says why.
  const ppcr::Status s = ppcr::voxel_downsample(cloud, std::ldexp(1.0, -21), &out);
  INFO(s.to_string());
  CHECK(s.code() == ppcr::StatusCode::kInvalidArgument);
  CHECK(s.message().find("too small") != std::string::npos);
  CHECK(s.message().find("2^21") != std::string::npos);
  // 2^20 + 1 cells: accepted, two voxels.
  REQUIRE(ppcr::voxel_downsample(cloud, std::ldexp(1.0, -20), &out).ok());
  CHECK(out == cloud);
  // A huge extent with a reasonable leaf.
  const PointCloud wide = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1e7, 0, 0)};
  CHECK(ppcr::voxel_downsample(wide, 1.0, &out).code() == ppcr::StatusCode::kInvalidArgument);
  // A leaf whose inverse overflows (here 0 * inf = NaN cells for a single point): refused.
  const PointCloud single = {Eigen::Vector3d(1, 2, 3)};
  CHECK(ppcr::voxel_downsample(single, std::numeric_limits<double>::denorm_min(), &out).code() ==
        ppcr::StatusCode::kInvalidArgument);
}

// Regression: the grid-size check once used floor((hi - lo) / leaf) + 1 <= 2^21 while the cell
// index uses floor((p - lo) * (1 / leaf)); the two roundings disagree here, so the point at z = e
// got z-index 2^21, which spilled into the next 21-bit field of the key (cell (0, 1, 0), the voxel
// of the third point) and merged the two. The check now uses the index's own expression, so this
// leaf is refused; keeping three points would be correct too, merging any two would not.
TEST_CASE("voxel_downsample: the highest cell index stays within its 21-bit field", "[voxel]") {
  const double e = 0.95928001510618488;
  const double leaf = 4.5742035632428407e-07;
  REQUIRE(std::floor(e / leaf) + 1.0 <= std::ldexp(1.0, 21));    // fits by division
  REQUIRE(std::floor(e * (1.0 / leaf)) == std::ldexp(1.0, 21));  // not by the key's rounding
  const PointCloud cloud = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, e),
                            Eigen::Vector3d(0, 1.5 * leaf, 0)};
  PointCloud out;
  const ppcr::Status s = ppcr::voxel_downsample(cloud, leaf, &out);
  if (s.ok()) {
    // Three points in three different voxels must stay three points.
    CHECK(out == cloud);
  } else {
    // Refusing the leaf as too small would also be correct.
    CHECK(s.code() == ppcr::StatusCode::kInvalidArgument);
    CHECK(s.message().find("too small") != std::string::npos);
  }
}

TEST_CASE("voxel_downsample: a leaf larger than the cloud gives its centroid", "[voxel]") {
  Rng rng(93);
  const PointCloud cloud = core_test::uniform_cloud(rng, 1000, -1.0, 1.0);
  PointCloud out;
  REQUIRE(ppcr::voxel_downsample(cloud, 10.0, &out).ok());
  REQUIRE(out.size() == 1u);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : cloud) sum += p;
  CHECK((out[0] - sum / 1000.0).norm() < 1e-15);
}

// The automatic leaf (preparation/automatic_voxel.hpp): about the asked number of points, the
// filter being voxel_downsample with the leaf reported; a smaller cloud untouched; the leaf scales
// with the cloud's units.
TEST_CASE("automatic voxel filter: about the asked points, unit-free, small clouds untouched",
          "[voxel]") {
  Rng rng(7);
  PointCloud surface;  // a wavy 4 x 3 sheet, 60,000 points
  for (int i = 0; i < 60000; ++i) {
    const double x = core_test::uniform(rng, -2.0, 2.0), y = core_test::uniform(rng, -1.5, 1.5);
    surface.emplace_back(x, y, 0.2 * std::sin(2 * x) * std::cos(y));
  }
  for (const std::size_t wanted : {std::size_t{2000}, std::size_t{10000}, std::size_t{30000}}) {
    PointCloud out;
    double leaf = 0.0;
    REQUIRE(ppcr::detail::automatic_voxel_filter(surface, wanted, &out, &leaf).ok());
    INFO(wanted << " wanted: " << out.size() << " kept, leaf " << leaf);
    CHECK(std::abs(static_cast<double>(out.size()) / wanted - 1.0) <= 0.15);
    PointCloud reference;
    REQUIRE(ppcr::voxel_downsample(surface, leaf, &reference).ok());
    CHECK(out == reference);
    // The same cloud in millimetres: the same points kept, the leaf x 1000.
    PointCloud millimetres, out_mm;
    for (const Eigen::Vector3d& p : surface) millimetres.push_back(1000.0 * p);
    double leaf_mm = 0.0;
    REQUIRE(ppcr::detail::automatic_voxel_filter(millimetres, wanted, &out_mm, &leaf_mm).ok());
    CHECK(out_mm.size() == out.size());
    CHECK(leaf_mm == Approx(1000.0 * leaf).epsilon(1e-9));
  }
  // Far from the origin (4 km) with a (0, 0, 0) placeholder point, 1000 times the cloud's extent
  // away: the far point does not set the leaf. (Georeferenced coordinates, millions of leaves
  // away, exceed voxel_downsample's 2^21 cells per axis: refused with its message.)
  PointCloud georeferenced;
  for (const Eigen::Vector3d& p : surface)
    georeferenced.push_back(p + Eigen::Vector3d(3e3, 2.5e3, 0));
  georeferenced.emplace_back(0.0, 0.0, 0.0);
  {
    PointCloud out;
    double leaf = 0.0;
    REQUIRE(ppcr::detail::automatic_voxel_filter(georeferenced, 10000, &out, &leaf).ok());
    INFO("kept " << out.size() << ", leaf " << leaf);
    CHECK(std::abs(static_cast<double>(out.size()) / 10000 - 1.0) <= 0.15);
  }
  PointCloud out;
  double leaf = 1.0;
  REQUIRE(ppcr::detail::automatic_voxel_filter(surface, 60000, &out, &leaf).ok());
  CHECK(leaf == 0.0);
  CHECK(out == surface);
  const PointCloud same(100, Eigen::Vector3d(1, 2, 3));  // one point, many times: not filtered
  REQUIRE(ppcr::detail::automatic_voxel_filter(same, 10, &out, &leaf).ok());
  CHECK(out == same);
  CHECK(leaf == 0.0);
}
