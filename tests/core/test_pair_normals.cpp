// Pair normals of the plane model with source normals (pair_normals.hpp), against a reference
// that picks the sign by comparing both candidate sums instead of by the dot product
// (pair_normal_reference.hpp).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "association/association_table.hpp"
#include "core_test_util.hpp"
#include "model/pair_normals.hpp"
#include "pair_normal_reference.hpp"

namespace {

using core_test::Rng;

struct Case {
  ppcr::detail::AssociationTable assoc;
  std::vector<Eigen::Vector3d> target_normals, source_normals;
  ppcr::detail::Buffer<ppcr::detail::PlanePoint>
      target_points;  // target_normals packed (at the origin)
  Eigen::Matrix3d R;
};

// Random table (k 5, counts 0..5) over 300 target points; every seventh target normal and every
// fifth source normal is zero ("no normal").
Case make_case(std::uint64_t seed) {
  Rng rng(seed);
  Case c;
  const std::size_t n_source = 800, n_target = 300;
  const int k = 5;
  c.assoc.resize(n_source, k);
  for (std::size_t j = 0; j < n_source; ++j) {
    const std::size_t count = static_cast<std::size_t>(rng() % (k + 1));
    c.assoc.count[j] = static_cast<std::uint16_t>(count);
    for (std::size_t m = 0; m < count; ++m) {
      c.assoc.index[j * k + m] = static_cast<std::uint32_t>(rng() % n_target);
    }
  }
  c.assoc.recount();
  c.target_normals.resize(n_target);
  for (std::size_t i = 0; i < n_target; ++i) {
    c.target_normals[i] = i % 7 == 0 ? Eigen::Vector3d::Zero() : core_test::random_unit_vector(rng);
  }
  ppcr::detail::pack_plane_points(ppcr::PointCloud(n_target, Eigen::Vector3d::Zero()),
                                  c.target_normals, 0.05, nullptr, &c.target_points);
  c.source_normals.resize(n_source);
  for (std::size_t j = 0; j < n_source; ++j) {
    c.source_normals[j] = j % 5 == 0 ? Eigen::Vector3d::Zero() : core_test::random_unit_vector(rng);
  }
  c.R =
      core_test::make_pose(Eigen::Vector3d(0.3, -1.0, 0.4), 0.9, Eigen::Vector3d::Zero()).linear();
  return c;
}

// Every row's pair normals, as the plane pass forms them (slots past a row's count stay NaN).
std::vector<ppcr::detail::PairNormal> run_raw(const Case& c) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<ppcr::detail::PairNormal> out(c.assoc.index.size(),
                                            {Eigen::Vector3d::Constant(nan), nan});
  const std::size_t k = static_cast<std::size_t>(c.assoc.k);
  for (std::size_t j = 0; j < c.assoc.count.size(); ++j) {
    ppcr::detail::pair_normals_of_point(c.R * c.source_normals[j], &c.assoc.index[j * k],
                                        c.assoc.count[j], c.target_points.data(), &out[j * k]);
  }
  return out;
}

// The unit normals s sqrt(q) = s / |s| they stand for (zero without a normal, NaN past a count).
std::vector<Eigen::Vector3d> run(const Case& c) {
  std::vector<Eigen::Vector3d> unit;
  for (const ppcr::detail::PairNormal& pn : run_raw(c)) unit.push_back(pn.s * std::sqrt(pn.q));
  return unit;
}

}  // namespace

TEST_CASE("pair normals equal the reference, slots past the count are not written",
          "[pair_normals]") {
  const Case c = make_case(301);
  const std::vector<Eigen::Vector3d> out = run(c);
  const std::size_t k = static_cast<std::size_t>(c.assoc.k);
  std::size_t zero_target = 0, zero_source = 0, flipped = 0, unused = 0;
  for (std::size_t j = 0; j < c.assoc.count.size(); ++j) {
    for (std::size_t m = 0; m < k; ++m) {
      const std::size_t slot = j * k + m;
      if (m >= c.assoc.count[j]) {
        CHECK(std::isnan(out[slot].x()));
        ++unused;
        continue;
      }
      const Eigen::Vector3d& n = c.target_normals[c.assoc.index[slot]];
      const Eigen::Vector3d& s = c.source_normals[j];
      const Eigen::Vector3d ref = core_test::reference_pair_normal(n, s, c.R);
      INFO("slot " << slot);
      CHECK((out[slot] - ref).norm() <= 1e-15);
      if (n.squaredNorm() == 0.0) {
        ++zero_target;
        CHECK(out[slot].squaredNorm() == 0.0);
      } else {
        CHECK(std::abs(out[slot].norm() - 1.0) < 1e-15);
        // On the target normal's side, and bisecting the two surfaces' normals.
        CHECK(out[slot].dot(n) > 0.7);
        if (s.squaredNorm() == 0.0) {
          ++zero_source;
        } else if (n.dot(c.R * s) < 0.0) {
          ++flipped;
        }
      }
    }
  }
  // Every branch was exercised.
  CHECK(zero_target > 50u);
  CHECK(zero_source > 50u);
  CHECK(flipped > 200u);
  CHECK(unused > 500u);
}

TEST_CASE("the same surface on both sides gives the target's normal, whatever the sign",
          "[pair_normals]") {
  Case c = make_case(302);
  const std::size_t k = static_cast<std::size_t>(c.assoc.k);
  // One target point per source point: its normal, brought into the source frame, with a sign
  // that alternates.
  for (std::size_t j = 0; j < c.assoc.count.size(); ++j) {
    if (c.assoc.count[j] == 0) continue;
    c.assoc.count[j] = 1;
    const Eigen::Vector3d& n = c.target_normals[c.assoc.index[j * k]];
    c.source_normals[j] = (j % 2 == 0 ? 1.0 : -1.0) * (c.R.transpose() * n);
  }
  c.assoc.recount();
  const std::vector<Eigen::Vector3d> out = run(c);
  for (std::size_t j = 0; j < c.assoc.count.size(); ++j) {
    if (c.assoc.count[j] == 0) continue;
    const Eigen::Vector3d& n = c.target_normals[c.assoc.index[j * k]];
    CHECK((out[j * k] - n).norm() <= 1e-15);
  }
}

// pair_normals_of_point takes two pairs per step in two lanes; each lane must round as the
// one-pair formula written out (s = n + sign(n . m) m, q = 1 / ((s_x^2 + s_y^2) + s_z^2)), so that
// the results do not depend on a pair's place in its list (an odd count leaves one pair to the
// one-pair path).
TEST_CASE("pair normals equal the one-pair formula to the bit, at every place in a list",
          "[pair_normals]") {
  for (std::uint64_t seed : {303u, 304u, 305u}) {
    const Case c = make_case(seed);
    const std::vector<ppcr::detail::PairNormal> out = run_raw(c);
    const std::size_t k = static_cast<std::size_t>(c.assoc.k);
    std::size_t compared = 0, second_lane = 0;
    for (std::size_t j = 0; j < c.assoc.count.size(); ++j) {
      const Eigen::Vector3d m = c.R * c.source_normals[j];
      for (std::size_t i = 0; i < c.assoc.count[j]; ++i) {
        const std::size_t slot = j * k + i;
        const Eigen::Vector3d& n = c.target_normals[c.assoc.index[slot]];
        Eigen::Vector3d want_s = Eigen::Vector3d::Zero();
        double want_q = 0.0;
        if (n.squaredNorm() != 0.0) {
          want_s = n.dot(m) >= 0.0 ? Eigen::Vector3d(n + m) : Eigen::Vector3d(n - m);
          want_q =
              1.0 / ((want_s.x() * want_s.x() + want_s.y() * want_s.y()) + want_s.z() * want_s.z());
          ++compared;
          second_lane += i % 2;
        }
        INFO("seed " << seed << " slot " << slot);
        CHECK(out[slot].s == want_s);
        CHECK(out[slot].q == want_q);
      }
    }
    CHECK(compared > 800u);
    CHECK(second_lane > 300u);
  }
}

// The memo an inner solve's first pass keeps (normal_equations.hpp, PairNormalMemo): the pair
// normals formed from it are those formed afresh, to the bit, for every row (target points with
// and without normals, source normals on either side, zero source normals); and the memo alone
// does not hold them (a memo of another rotation's pass gives other normals).
TEST_CASE("pair normals from the memo equal those formed afresh, to the bit", "[pair_normals]") {
  const Case c = make_case(306);
  const std::size_t k = static_cast<std::size_t>(c.assoc.k);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<ppcr::detail::PairNormal> fresh = run_raw(c);
  std::vector<double> memo(c.assoc.index.size(), nan);
  std::vector<ppcr::detail::PairNormal> kept(c.assoc.index.size(),
                                             {Eigen::Vector3d::Constant(nan), nan});
  std::vector<ppcr::detail::PairNormal> from_memo = kept;
  std::size_t compared = 0, negated = 0, zero = 0;
  for (std::size_t j = 0; j < c.assoc.count.size(); ++j) {
    const Eigen::Vector3d m = c.R * c.source_normals[j];
    const std::uint32_t* idx = &c.assoc.index[j * k];
    const std::size_t count = c.assoc.count[j];
    ppcr::detail::pair_normals_of_point(m, idx, count, c.target_points.data(), &kept[j * k],
                                        &memo[j * k]);
    ppcr::detail::pair_normals_from_memo(m, idx, count, c.target_points.data(), &memo[j * k],
                                         &from_memo[j * k]);
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t slot = j * k + i;
      INFO("slot " << slot);
      // Writing the memo leaves the pass's own normals as they were.
      CHECK(kept[slot].s == fresh[slot].s);
      CHECK(kept[slot].q == fresh[slot].q);
      CHECK(from_memo[slot].s == fresh[slot].s);
      CHECK(from_memo[slot].q == fresh[slot].q);
      ++compared;
      negated += std::signbit(memo[slot]);
      zero += fresh[slot].q == 0.0;
    }
  }
  CHECK(compared > 1500u);
  CHECK(negated > 200u);
  CHECK(zero > 50u);
  // The memo holds the sign chosen at this rotation: read with another source normal direction
  // (m negated), the normals differ wherever there is one.
  std::size_t differ = 0;
  for (std::size_t j = 0; j < c.assoc.count.size(); ++j) {
    const Eigen::Vector3d m = -(c.R * c.source_normals[j]);
    std::vector<ppcr::detail::PairNormal> other(k);
    ppcr::detail::pair_normals_from_memo(m, &c.assoc.index[j * k], c.assoc.count[j],
                                         c.target_points.data(), &memo[j * k], other.data());
    for (std::size_t i = 0; i < c.assoc.count[j]; ++i) {
      differ += fresh[j * k + i].q > 0.0 && c.source_normals[j].squaredNorm() > 0.0 &&
                !(other[i].s == fresh[j * k + i].s);
    }
  }
  CHECK(differ > 1000u);
}
