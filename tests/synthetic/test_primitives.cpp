// Ray-primitive intersections of ppcr_synthetic against references: hand-computed cases, and
// random rays compared with a brute-force march (small steps along the ray until the
// point-in-solid test of scene_reference.hpp changes, then bisection).
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <random>

#include "scene_reference.hpp"
#include "synthetic/primitives.hpp"

namespace {

using ppcr::synthetic::internal::Box;
using ppcr::synthetic::internal::Cylinder;
using ppcr::synthetic::internal::intersect;
using ppcr::synthetic::internal::kNoHit;
using ppcr::synthetic::internal::Ray;
using ppcr::synthetic::internal::Rectangle;
using ppcr::synthetic::internal::Sphere;

const double kInf = std::numeric_limits<double>::infinity();
const double kPi = std::acos(-1.0);

Ray make_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& toward) {
  return {origin, (toward - origin).normalized()};
}

Eigen::Vector3d point_at(const Ray& ray, double t) { return ray.origin + t * ray.direction; }

/// First t in (0, t_end] where predicate(point) differs from its value at the origin, found by
/// marching with `step` then bisecting to 1e-14; kInf when the march sees no change.
double march(const Ray& ray, const std::function<bool(const Eigen::Vector3d&)>& predicate,
             double t_end, double step) {
  const bool start = predicate(ray.origin);
  double previous = 0.0;
  for (double t = step; t <= t_end + step; t += step) {
    if (predicate(point_at(ray, t)) != start) {
      double lo = previous;
      double hi = t;
      while (hi - lo > 1e-14) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;  // adjacent doubles
        if (predicate(point_at(ray, mid)) != start) {
          hi = mid;
        } else {
          lo = mid;
        }
      }
      return hi;
    }
    previous = t;
  }
  return kInf;
}

/// Compares the analytic first hit with the march. Where they disagree, the analytic hit must
/// be a crossing too thin for the coarse march: a fine march (step 1e-7) started just before it
/// must find a crossing there.
template <typename Primitive>
void check_against_march(const Ray& ray, const Primitive& primitive,
                         const std::function<bool(const Eigen::Vector3d&)>& predicate, double t_end,
                         double step, int* thin_cases) {
  const double analytic = intersect(ray, primitive, 0.0, kInf);
  const double reference = march(ray, predicate, t_end, step);
  if (analytic != kInf) {
    // The hit point is on the surface (independent distance function).
    REQUIRE(synth_test::surface_distance(point_at(ray, analytic), primitive) < 1e-12);
  }
  if (reference == kInf && analytic == kInf) return;
  if (reference != kInf && analytic != kInf && std::abs(reference - analytic) < 1e-9) return;
  // Disagreement: only allowed for a thin crossing that the coarse march stepped over, which
  // lies before the march's first crossing.
  REQUIRE(analytic != kInf);
  REQUIRE(analytic < reference);
  const double t0 = std::max(0.0, analytic - 2 * step);
  const Ray shifted{point_at(ray, t0), ray.direction};
  const bool same_state_at_start = predicate(shifted.origin) == predicate(ray.origin);
  REQUIRE(same_state_at_start);
  const double fine = march(shifted, predicate, 4 * step, 1e-7);
  REQUIRE(fine != kInf);
  // Within one fine step: for a chord shorter than that, the bisection may converge to its exit.
  REQUIRE(std::abs(t0 + fine - analytic) < 1e-7);
  ++*thin_cases;
}

Eigen::Matrix3d random_rotation(std::mt19937_64* engine) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(*engine), normal(*engine), normal(*engine), normal(*engine));
  return q.normalized().toRotationMatrix();
}

Eigen::Vector3d random_point(std::mt19937_64* engine, double half) {
  std::uniform_real_distribution<double> u(-half, half);
  return Eigen::Vector3d(u(*engine), u(*engine), u(*engine));
}

}  // namespace

TEST_CASE("ray-rectangle: hand-computed hits and misses", "[synthetic][primitives]") {
  const Rectangle floor{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitX(),
                        Eigen::Vector3d::UnitY(), 2.0, 1.0};
  // Straight down from height 3: t = 3. From below (two-sided): t = 1.
  CHECK(intersect(make_ray({0.5, 0.5, 3}, {0.5, 0.5, 0}), floor, 0.0, kInf) == Approx(3.0));
  CHECK(intersect(make_ray({0.5, 0.5, -1}, {0.5, 0.5, 0}), floor, 0.0, kInf) == Approx(1.0));
  // 45 degrees: from (0,0,1) toward (1,0,0): t = sqrt(2).
  CHECK(intersect(make_ray({0, 0, 1}, {1, 0, 0}), floor, 0.0, kInf) == Approx(std::sqrt(2.0)));
  // Outside the extent (|y| = 1.5 > 1), parallel, pointing away, beyond t_max.
  CHECK(intersect(make_ray({0, 1.5, 1}, {0, 1.5, 0}), floor, 0.0, kInf) == kNoHit);
  CHECK(intersect(Ray{{0, 0, 1}, {1, 0, 0}}, floor, 0.0, kInf) == kNoHit);
  CHECK(intersect(Ray{{0, 0, 1}, {0, 0, 1}}, floor, 0.0, kInf) == kNoHit);
  CHECK(intersect(make_ray({0.5, 0.5, 3}, {0.5, 0.5, 0}), floor, 0.0, 2.5) == kNoHit);
}

TEST_CASE("ray-box: hand-computed hits and misses", "[synthetic][primitives]") {
  // Unit cube about (5, 0, 0), then the same cube turned 45 degrees about z.
  Box box{Eigen::Vector3d(5, 0, 0), Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 1, 1)};
  CHECK(intersect(Ray{{0, 0, 0}, {1, 0, 0}}, box, 0.0, kInf) == Approx(4.0));
  CHECK(intersect(Ray{{0, 0.5, 0.5}, {1, 0, 0}}, box, 0.0, kInf) == Approx(4.0));
  CHECK(intersect(Ray{{0, 1.5, 0}, {1, 0, 0}}, box, 0.0, kInf) == kNoHit);     // parallel, outside
  CHECK(intersect(Ray{{0, 0, 0}, {-1, 0, 0}}, box, 0.0, kInf) == kNoHit);      // pointing away
  CHECK(intersect(Ray{{5, 0, 0}, {0, 1, 0}}, box, 0.0, kInf) == Approx(1.0));  // from inside
  box.axes = Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  // The near vertex of the turned cube is at x = 5 - sqrt(2).
  CHECK(intersect(Ray{{0, 0, 0}, {1, 0, 0}}, box, 0.0, kInf) == Approx(5.0 - std::sqrt(2.0)));
}

TEST_CASE("ray-sphere: hand-computed hits and misses", "[synthetic][primitives]") {
  const Sphere ball{Eigen::Vector3d(5, 0, 0), 1.0};
  CHECK(intersect(Ray{{0, 0, 0}, {1, 0, 0}}, ball, 0.0, kInf) == Approx(4.0));
  CHECK(intersect(Ray{{5, 0, 0}, {0, 0, 1}}, ball, 0.0, kInf) == Approx(1.0));  // from inside
  // Offset by 0.6: chord half length 0.8, so t = 5 - 0.8.
  CHECK(intersect(Ray{{0, 0.6, 0}, {1, 0, 0}}, ball, 0.0, kInf) == Approx(4.2));
  CHECK(intersect(Ray{{0, 1.01, 0}, {1, 0, 0}}, ball, 0.0, kInf) == kNoHit);
  CHECK(intersect(Ray{{0, 0, 0}, {-1, 0, 0}}, ball, 0.0, kInf) == kNoHit);
  // A small far sphere (the discriminant form that avoids cancellation): 1 mm ball at 10 km.
  const Sphere far{Eigen::Vector3d(1e4, 0, 0), 1e-3};
  CHECK(intersect(Ray{{0, 0, 0}, {1, 0, 0}}, far, 0.0, kInf) == Approx(1e4 - 1e-3).epsilon(1e-15));
}

TEST_CASE("ray-cylinder: hand-computed hits and misses", "[synthetic][primitives]") {
  // Vertical pole of radius 0.5 and height 2 at (4, 0, 0).
  const Cylinder pole{Eigen::Vector3d(4, 0, 0), Eigen::Vector3d::UnitZ(), 2.0, 0.5};
  CHECK(intersect(Ray{{0, 0, 1}, {1, 0, 0}}, pole, 0.0, kInf) == Approx(3.5));     // side
  CHECK(intersect(Ray{{0, 0, 3}, {1, 0, 0}}, pole, 0.0, kInf) == kNoHit);          // above
  CHECK(intersect(Ray{{4, 0.2, 5}, {0, 0, -1}}, pole, 0.0, kInf) == Approx(3.0));  // top cap
  CHECK(intersect(Ray{{4, 0.2, -1}, {0, 0, 1}}, pole, 0.0, kInf) == Approx(1.0));  // bottom cap
  CHECK(intersect(Ray{{4, 0.6, 5}, {0, 0, -1}}, pole, 0.0, kInf) == kNoHit);    // parallel, beside
  CHECK(intersect(Ray{{4, 0, 1}, {0, 1, 0}}, pole, 0.0, kInf) == Approx(0.5));  // from inside
  // Tilted axis: a horizontal barrel along y through the origin, radius 1; ray down from z = 3.
  const Cylinder barrel{Eigen::Vector3d(0, -2, 0), Eigen::Vector3d::UnitY(), 4.0, 1.0};
  CHECK(intersect(Ray{{0, 0, 3}, {0, 0, -1}}, barrel, 0.0, kInf) == Approx(2.0));
  CHECK(intersect(Ray{{0.6, 0, 3}, {0, 0, -1}}, barrel, 0.0, kInf) == Approx(2.2));
}

TEST_CASE("ray-primitive intersections match a brute-force march", "[synthetic][primitives]") {
  std::mt19937_64 engine(20240607);
  std::uniform_real_distribution<double> size(0.3, 1.5);
  const double step = 1e-3;
  int thin = 0;
  int hits = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d center = random_point(&engine, 1.0);
    const Eigen::Matrix3d axes = random_rotation(&engine);
    const Box box{center, axes, Eigen::Vector3d(size(engine), size(engine), size(engine))};
    const Sphere sphere{center, size(engine)};
    const Cylinder cylinder{center - 0.7 * axes.col(2), axes.col(2), 1.4 * size(engine),
                            0.6 * size(engine)};
    const Rectangle rectangle{center, axes.col(0), axes.col(1), size(engine), size(engine)};
    for (int r = 0; r < 4; ++r) {
      // Origins mostly outside (some inside), aimed at points near the primitive.
      const Eigen::Vector3d origin = random_point(&engine, 5.0);
      const Ray ray = make_ray(origin, center + random_point(&engine, 1.6));
      // Every primitive lies within 2.7 m of `center`: the march can stop beyond that.
      const double t_end = (origin - center).norm() + 3.0;
      check_against_march(
          ray, box, [&](const Eigen::Vector3d& p) { return synth_test::inside(p, box); }, t_end,
          step, &thin);
      check_against_march(
          ray, sphere, [&](const Eigen::Vector3d& p) { return synth_test::inside(p, sphere); },
          t_end, step, &thin);
      check_against_march(
          ray, cylinder, [&](const Eigen::Vector3d& p) { return synth_test::inside(p, cylinder); },
          t_end, step, &thin);
      // Rectangle: the predicate is the side of its plane; a crossing counts when the crossing
      // point is within the rectangle's extent.
      const Eigen::Vector3d normal = rectangle.u.cross(rectangle.v);
      const double t_plane = march(
          ray, [&](const Eigen::Vector3d& p) { return normal.dot(p - rectangle.center) > 0; },
          t_end, step);
      const bool within =
          t_plane != kInf && synth_test::surface_distance(point_at(ray, t_plane), rectangle) < 1e-9;
      const double analytic = intersect(ray, rectangle, 0.0, kInf);
      if (within) {
        REQUIRE(analytic == Approx(t_plane).margin(1e-9));
        REQUIRE(synth_test::surface_distance(point_at(ray, analytic), rectangle) < 1e-12);
      } else if (analytic != kInf) {  // only a crossing within 1e-9 of the border may differ
        REQUIRE(synth_test::surface_distance(point_at(ray, analytic), rectangle) < 1e-9);
      }
      hits += intersect(ray, box, 0.0, kInf) != kNoHit;
    }
  }
  // The rays do test hits (not only misses), and thin crossings stay rare.
  CHECK(hits > 200);
  CHECK(thin < 20);
}

TEST_CASE("ray from a surface point: t_min excludes the start", "[synthetic][primitives]") {
  const Sphere ball{Eigen::Vector3d(0, 0, 0), 1.0};
  // Starting on the surface, going inwards: the next hit is the far side, t = 2.
  CHECK(intersect(Ray{{-1, 0, 0}, {1, 0, 0}}, ball, 1e-9, kInf) == Approx(2.0));
  const Box box{Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 1, 1)};
  CHECK(intersect(Ray{{-1, 0, 0}, {1, 0, 0}}, box, 1e-9, kInf) == Approx(2.0));
}

TEST_CASE("signed distances agree with the reference surface distances",
          "[synthetic][primitives]") {
  std::mt19937_64 engine(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d axes = random_rotation(&engine);
    const Box box{random_point(&engine, 1.0), axes, Eigen::Vector3d(0.5, 1.0, 1.5)};
    const Sphere sphere{random_point(&engine, 1.0), 0.8};
    const Cylinder cylinder{random_point(&engine, 1.0), axes.col(1), 2.0, 0.7};
    for (int k = 0; k < 10; ++k) {
      const Eigen::Vector3d p = random_point(&engine, 3.0);
      using ppcr::synthetic::internal::signed_distance;
      const double db = signed_distance(p, box);
      CHECK(std::abs(db) == Approx(synth_test::surface_distance(p, box)).margin(1e-12));
      CHECK((db < 0) == synth_test::inside(p, box));
      const double ds = signed_distance(p, sphere);
      CHECK(std::abs(ds) == Approx(synth_test::surface_distance(p, sphere)).margin(1e-12));
      CHECK((ds < 0) == synth_test::inside(p, sphere));
      const double dc = signed_distance(p, cylinder);
      CHECK(std::abs(dc) == Approx(synth_test::surface_distance(p, cylinder)).margin(1e-12));
      CHECK((dc < 0) == synth_test::inside(p, cylinder));
    }
  }
}
