// normal_equations.cpp - fused residuals / weights / normal equations pass (see header).
#include "model/normal_equations.hpp"

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "common/parallel.hpp"
#include "model/e_step_kernel.hpp"
#include "model/four_lanes.hpp"
#include "model/four_points.hpp"
#include "model/pair_normals.hpp"
#include "ppcr/se3.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {
namespace {

// Omega = a I + n n^T of a target point (ppcr/options.hpp, ErrorModel): a = epsilon with a normal,
// else 1.
inline double omega_isotropic(const Eigen::Vector3d& n, double epsilon) {
  return n.squaredNorm() > 0.0 ? epsilon : 1.0;
}

// Obar_j of the plane model: symmetric, its six entries.
struct Sym3 {
  double xx, yy, zz, xy, yz, xz;
};

// Adds one source point's plane-model terms (header) to the block's H and g sums, with
// J = [ [p]_x | -I ]: H_tl += [p]_x Obar [p]_x^T, H_tr += [p]_x Obar, H_br += Obar, and ebar,
// ebar x p. Only the upper triangles of H's diagonal blocks are written (evaluate() completes H
// by symmetry). With M = [p]_x Obar, column c of M is p x (column c of Obar), and row r of the
// top-left block M [p]_x^T is (p x M_r)^T, M_r the r-th row of M: cross products instead of two
// general 3x3 products.
inline void add_plane_point(const Eigen::Vector3d& p, const Sym3& o, const Eigen::Vector3d& ebar,
                            Matrix6d* H, Eigen::Vector3d* ebar_sum, Eigen::Vector3d* ebar_cross_p) {
  Eigen::Matrix3d M;
  M.col(0) = p.cross(Eigen::Vector3d(o.xx, o.xy, o.xz));
  M.col(1) = p.cross(Eigen::Vector3d(o.xy, o.yy, o.yz));
  M.col(2) = p.cross(Eigen::Vector3d(o.xz, o.yz, o.zz));
  const Eigen::Vector3d row0 = p.cross(Eigen::Vector3d(M.row(0).transpose()));
  const Eigen::Vector3d m1 = M.row(1).transpose(), m2 = M.row(2).transpose();
  (*H)(0, 0) += row0.x();
  (*H)(0, 1) += row0.y();
  (*H)(0, 2) += row0.z();
  (*H)(1, 1) += p.z() * m1.x() - p.x() * m1.z();  // (p x M_1)_y
  (*H)(1, 2) += p.x() * m1.y() - p.y() * m1.x();  // (p x M_1)_z
  (*H)(2, 2) += p.x() * m2.y() - p.y() * m2.x();  // (p x M_2)_z
  H->topRightCorner<3, 3>() += M;
  (*H)(3, 3) += o.xx;
  (*H)(3, 4) += o.xy;
  (*H)(3, 5) += o.xz;
  (*H)(4, 4) += o.yy;
  (*H)(4, 5) += o.yz;
  (*H)(5, 5) += o.zz;
  *ebar_sum += ebar;
  *ebar_cross_p += ebar.cross(p);
}

}  // namespace

void pack_plane_points(const PointCloud& target, const std::vector<Eigen::Vector3d>& normals,
                       double epsilon, const Parallel* parallel, Buffer<PlanePoint>* out,
                       Buffer<PlaneInformation>* information) {
  out->resize(target.size());
  if (information != nullptr) information->resize(target.size());
  parallel_for(parallel, static_cast<std::ptrdiff_t>(target.size()), [&](std::ptrdiff_t j) {
    const std::size_t i = static_cast<std::size_t>(j);
    PlanePoint& q = (*out)[i];
    const Eigen::Vector3d& n = normals[i];
    q.y = target[i];
    q.n = n;
    q.a = omega_isotropic(n, epsilon);
    const Eigen::Vector3d b = q.a * q.y + n * n.dot(q.y);  // Omega y
    q.b_z = b.z();
    if (information == nullptr) return;
    PlaneInformation& o = (*information)[i];
    o.omega_xx_yy[0] = q.a + n.x() * n.x();
    o.omega_xx_yy[1] = q.a + n.y() * n.y();
    o.omega_xy_yz[0] = n.x() * n.y();
    o.omega_xy_yz[1] = n.y() * n.z();
    o.omega_xz_zz[0] = n.x() * n.z();
    o.omega_xz_zz[1] = q.a + n.z() * n.z();
    o.b_xy[0] = b.x();
    o.b_xy[1] = b.y();
  });
}

void NormalEquations::resize(std::size_t source_points, int k) {
  blocks_.resize(block_count(source_points, kBlockSize));
  pair_normals_.resize(blocks_.size() * static_cast<std::size_t>(k));
}

namespace {

// The squared errors r[m] of point p's count pairs (Mahalanobis for the plane model); returns
// their smallest, as smallest() (e_step_kernel.hpp) takes it.
template <bool kPlane, bool kPairNormals>
inline double squared_errors(const Eigen::Vector3d& p, std::size_t count, const std::uint32_t* idx,
                             const PointCloud& target, const PlanePoint* points,
                             const PairNormal* pair_normals, double epsilon, double* r) {
  double r_min = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t m = 0; m < count; ++m) {
    double rm;
    if constexpr (kPlane) {
      const PlanePoint& q = points[idx[m]];
      const Eigen::Vector3d e = q.y - p;
      if constexpr (kPairNormals) {
        // a |e|^2 + (n . e)^2 with n = s / |s|: a |e|^2 + q (s . e)^2.
        const PairNormal& nk = pair_normals[m];
        const double se = dot_in_order(nk.s, e);
        rm = pair_isotropic(nk, epsilon) * dot_in_order(e, e) + nk.q * (se * se);
      } else {
        const double ne = q.n.dot(e);
        rm = q.a * e.squaredNorm() + ne * ne;
      }
    } else {
      rm = (target[idx[m]] - p).squaredNorm();
    }
    r[m] = rm;
    r_min = m == 0 || rm < r_min ? rm : r_min;
  }
  return r_min;
}

// Plane model, target normals: O = sum_k u_k Omega_k (symmetric: 6 sums), B = sum_k u_k b_k,
// U = sum_k u_k, in pairs of lanes (Eigen::Array2d: one SSE2 / NEON operation for two); then
// Obar = c O and ebar = c B - Obar p (PlaneInformation). Scales w by c.
inline void accumulate_plane(const Eigen::Vector3d& p, std::size_t count, const std::uint32_t* idx,
                             const PlanePoint* points, const PlaneInformation* information,
                             const double* r, double c, double* w, BlockSums* s) {
  Eigen::Array2d o_xx_yy = Eigen::Array2d::Zero();
  Eigen::Array2d o_xy_yz = Eigen::Array2d::Zero();
  Eigen::Array2d o_xz_zz = Eigen::Array2d::Zero();
  Eigen::Array2d b_xy = Eigen::Array2d::Zero();
  double b_z = 0.0, U = 0.0, ur = 0.0;
  for (std::size_t m = 0; m < count; ++m) {
    const double u = w[m];
    const PlaneInformation& o = information[idx[m]];
    const Eigen::Array2d uu = Eigen::Array2d::Constant(u);
    o_xx_yy += uu * Eigen::Map<const Eigen::Array2d>(o.omega_xx_yy);
    o_xy_yz += uu * Eigen::Map<const Eigen::Array2d>(o.omega_xy_yz);
    o_xz_zz += uu * Eigen::Map<const Eigen::Array2d>(o.omega_xz_zz);
    b_xy += uu * Eigen::Map<const Eigen::Array2d>(o.b_xy);
    b_z += u * points[idx[m]].b_z;
    U += u;
    ur += u * r[m];
    w[m] *= c;
  }
  const Sym3 Obar{c * o_xx_yy[0], c * o_xx_yy[1], c * o_xz_zz[1],
                  c * o_xy_yz[0], c * o_xy_yz[1], c * o_xz_zz[0]};
  // ebar = c B - Obar p
  const Eigen::Vector3d ebar(c * b_xy[0] - (Obar.xx * p.x() + Obar.xy * p.y() + Obar.xz * p.z()),
                             c * b_xy[1] - (Obar.xy * p.x() + Obar.yy * p.y() + Obar.yz * p.z()),
                             c * b_z - (Obar.xz * p.x() + Obar.yz * p.y() + Obar.zz * p.z()));
  add_plane_point(p, Obar, ebar, &s->H, &s->ebar, &s->ebar_cross_p);
  s->cost += c * ur;
  s->S0 += c * U;
}

// Plane model, pair normals: a normal per slot, not per target point, so no moments; Omega_kj is
// formed from the pair's normal n_k = s_k / |s_k| here, as q_k s_k s_k^T (PairNormal).
// Obar = c (A I + N), N = sum_k u_k q_k s_k s_k^T (symmetric: 6 sums), ebar = c sum_k u_k (a_k
// e_k + q_k s_k (s_k . e_k)). The sums are kept in pairs of lanes; each lane does one sum's scalar
// operations in the scalar order (s . e as (x + y) + z), so every sum is the same to the bit as
// when written one by one (our targets are compiled with -ffp-contract=off: no a * b + c is fused
// into a multiply-add; tested with -march=haswell, the fma stage of tools/test.sh). Scales w by c.
inline void accumulate_pair_normals(const Eigen::Vector3d& p, std::size_t count,
                                    const std::uint32_t* idx, const PlanePoint* points,
                                    const PairNormal* pair_normals, double epsilon, const double* r,
                                    double c, double* w, BlockSums* s) {
  Eigen::Array2d AU = Eigen::Array2d::Zero();       // (A, U): sum u a, sum u
  Eigen::Array2d n00_n11 = Eigen::Array2d::Zero();  // (N_00, N_11)
  Eigen::Array2d n01_n12 = Eigen::Array2d::Zero();  // (N_01, N_12)
  Eigen::Array2d n02_n22 = Eigen::Array2d::Zero();  // (N_02, N_22)
  Eigen::Array2d bxy = Eigen::Array2d::Zero();      // (ebar_x, ebar_y) / c
  double bz = 0.0, ur = 0.0;
  const Eigen::Array2d p_xy(p.x(), p.y());
  for (std::size_t m = 0; m < count; ++m) {
    const double u = w[m];
    const PlanePoint& q = points[idx[m]];
    const PairNormal& nk = pair_normals[m];
    const double ak = pair_isotropic(nk, epsilon);
    const Eigen::Array2d n_xy = Eigen::Map<const Eigen::Array2d>(nk.s.data());
    const Eigen::Array2d n_yz = Eigen::Map<const Eigen::Array2d>(nk.s.data() + 1);
    const double nz = nk.s.z();
    const Eigen::Array2d e_xy = Eigen::Map<const Eigen::Array2d>(q.y.data()) - p_xy;
    const double ez = q.y.z() - p.z();
    const Eigen::Array2d ne_xy = n_xy * e_xy;
    const double ua = u * ak;
    const double uq = u * nk.q;
    const double une = uq * (ne_xy[0] + ne_xy[1] + nz * ez);  // u q (s . e)
    const Eigen::Array2d un_xy = uq * n_xy;
    const double unz = uq * nz;
    AU += Eigen::Array2d(ua, u);
    ur += u * r[m];
    n00_n11 += un_xy * n_xy;
    n01_n12 += un_xy * n_yz;
    n02_n22 += Eigen::Array2d(un_xy[0], unz) * nz;
    bxy += ua * e_xy + une * n_xy;
    bz += ua * ez + une * nz;
    w[m] *= c;
  }
  const double A = AU[0], U = AU[1];
  const double n00 = n00_n11[0], n11 = n00_n11[1], n01 = n01_n12[0], n12 = n01_n12[1];
  const double n02 = n02_n22[0], n22 = n02_n22[1], bx = bxy[0], by = bxy[1];
  const Sym3 Obar{c * (n00 + A), c * (n11 + A), c * (n22 + A), c * n01, c * n12, c * n02};
  add_plane_point(p, Obar, c * Eigen::Vector3d(bx, by, bz), &s->H, &s->ebar, &s->ebar_cross_p);
  s->cost += c * ur;
  s->S0 += c * U;
}

// Point model: W_j, sum_k w y_k and the cost, accumulated with u and scaled by c once.
inline void accumulate_point(const Eigen::Vector3d& p, std::size_t count, const std::uint32_t* idx,
                             const PointCloud& target, const double* r, double c, double* w,
                             BlockSums* s) {
  double U = 0.0, ur = 0.0;
  Eigen::Vector3d uy = Eigen::Vector3d::Zero();
  for (std::size_t m = 0; m < count; ++m) {
    U += w[m];
    ur += w[m] * r[m];
    uy += w[m] * target[idx[m]];
    w[m] *= c;
  }
  const double W = c * U;
  const Eigen::Vector3d ebar = c * uy - W * p;  // sum_k w_kj e_kj
  s->cost += c * ur;
  s->S0 += W;
  s->S1 += W * p;
  s->S2.noalias() += (W * p) * p.transpose();
  s->ebar += ebar;
  s->ebar_cross_p += ebar.cross(p);  // [p]_x^T ebar = ebar x p
}

// What every point of one pass reads, and where it writes.
struct PassContext {
  const PointCloud* source;
  const PointCloud* target;
  const AssociationTable* assoc;
  Eigen::Matrix3d R;  // the pose T = (R, t)
  Eigen::Vector3d t;
  const PlanePoint* points;               // plane model: the target's records
  const PlaneInformation* information;    // plane model without pair normals
  const Eigen::Vector3d* source_normals;  // pair normals: the source's normals, rotated by R_pair
  Eigen::Matrix3d R_pair;
  double epsilon;
  PairNormalMode pair_mode;
  PairNormalMemo memo;
  const double* w_prev;  // null, or the weights before (cost_prev)
  double* w_new;
  double* r_sq;  // null, or room for every pair's squared error
  std::size_t k;
};

// One source point's pairs: pair normals, squared errors, E-step, sums. Without r_sq its squared
// errors live in r_local (read back within the point); its pairs' normals in normals_local.
template <bool kPlane, bool kPairNormals, class Kernel>
void point_terms(const PassContext& c, const Kernel& e_step, std::size_t j,
                 PairNormal* normals_local, double* r_local, BlockSums* s) {
  const std::size_t count = c.assoc->count[j];
  const std::size_t slot = j * c.k;
  const std::uint32_t* idx = &c.assoc->index[slot];
  double* r = c.r_sq != nullptr ? &c.r_sq[slot] : r_local;
  double* w = &c.w_new[slot];
  const PairNormal* normals = nullptr;
  if constexpr (kPairNormals) {
    const Eigen::Vector3d m = c.R_pair * c.source_normals[j];
    if (c.pair_mode != PairNormalMode::kFromMemo) {
      pair_normals_of_point(m, idx, count, c.points, normals_local,
                            c.memo.slots != nullptr ? &c.memo.slots[slot] : nullptr);
    } else {
      pair_normals_from_memo(m, idx, count, c.points, &c.memo.slots[slot], normals_local);
    }
    normals = normals_local;
  }
  const Eigen::Vector3d p = c.R * (*c.source)[j] + c.t;
  const double r_min = squared_errors<kPlane, kPairNormals>(p, count, idx, *c.target, c.points,
                                                            normals, c.epsilon, r);
  if (c.w_prev != nullptr) {  // read before the E-step writes w (w_prev may be w_new)
    const double* wp = &c.w_prev[slot];
    for (std::size_t m = 0; m < count; ++m) s->cost_prev += wp[m] * r[m];
  }
  // E-step at this pose (eq. 2-4): w = c * u.
  const PointWeights pw = e_step(r, r_min, count, w);
  if constexpr (kPlane && !kPairNormals) {
    accumulate_plane(p, count, idx, c.points, c.information, r, pw.c, w, s);
  } else if constexpr (kPlane) {
    accumulate_pair_normals(p, count, idx, c.points, normals, c.epsilon, r, pw.c, w, s);
  } else {
    accumulate_point(p, count, idx, *c.target, r, pw.c, w, s);
  }
}

// Four points with count pairs each through four_point_terms() (the same bits as point_terms), or
// one at a time where their errors overflow.
template <class Kernel>
void four_point_rows(const PassContext& c, const Kernel& e_step, const std::size_t waiting[4],
                     std::size_t count, const DyadicStudentT& four_points,
                     PairNormal* normals_local, double* r_local, BlockSums* s) {
  FourPointRow rows[4];
  for (int l = 0; l < 4; ++l) {
    const std::size_t slot = waiting[l] * c.k;
    rows[l].p_target = c.R * (*c.source)[waiting[l]] + c.t;
    rows[l].normal_target = c.R_pair * c.source_normals[waiting[l]];
    rows[l].idx = &c.assoc->index[slot];
    rows[l].w_prev = c.w_prev != nullptr ? &c.w_prev[slot] : nullptr;
    rows[l].memo = c.memo.slots != nullptr ? &c.memo.slots[slot] : nullptr;
    rows[l].r_sq = c.r_sq != nullptr ? &c.r_sq[slot] : nullptr;
    rows[l].w = &c.w_new[slot];
  }
  if (!four_point_terms(rows, count, c.points, c.epsilon, c.pair_mode, four_points, s)) {
    for (int l = 0; l < 4; ++l) {
      point_terms<true, true>(c, e_step, waiting[l], normals_local, r_local, s);
    }
  }
}

}  // namespace

template <bool kPlane, bool kPairNormals, class Kernel>
void NormalEquations::pass(const Kernel& e_step, const PointCloud& source, const PointCloud& target,
                           const AssociationTable& assoc, const Eigen::Isometry3d& T,
                           const double* w_prev, double* w_new, double* r_sq,
                           const Parallel* parallel, const PlaneModel* plane, PairNormalMemo memo,
                           const DyadicStudentT* four_points) {
  PassContext c;
  c.source = &source;
  c.target = &target;
  c.assoc = &assoc;
  c.R = T.linear();
  c.t = T.translation();
  c.points = kPlane ? plane->points->data() : nullptr;
  c.information = kPlane && !kPairNormals ? plane->information->data() : nullptr;
  // Pair normals (source normals on) replace the target points' normals: formed per point from
  // the row's source normal (kPairNormals: a template parameter, so that the per-pair choice is
  // compiled out).
  c.source_normals = kPairNormals ? plane->pair_source->normals->data() : nullptr;
  c.R_pair = kPairNormals ? plane->pair_source->R_target_source : Eigen::Matrix3d::Identity();
  c.epsilon = kPlane ? plane->epsilon : 1.0;
  c.pair_mode = memo.slots == nullptr ? PairNormalMode::kFresh
                : memo.fill           ? PairNormalMode::kFill
                                      : PairNormalMode::kFromMemo;
  c.memo = memo;
  c.w_prev = w_prev;
  c.w_new = w_new;
  c.r_sq = r_sq;
  c.k = static_cast<std::size_t>(assoc.k);
  const std::uint8_t* left_out = assoc.any_left_out ? assoc.left_out.data() : nullptr;

  parallel_for_blocks(
      parallel, source.size(), kBlockSize,
      [&](std::ptrdiff_t b, std::size_t begin, std::size_t end) {
        double r_local[AssociationTable::kMaxNeighbours];
        PairNormal* normals_local =
            kPairNormals ? &pair_normals_[static_cast<std::size_t>(b) * c.k] : nullptr;
        BlockSums s;
        s.S0 = s.cost = s.cost_prev = 0.0;
        s.S1.setZero();
        s.ebar.setZero();
        s.ebar_cross_p.setZero();
        s.S2.setZero();
        s.H.setZero();
        // With four_points, runs of four points with the same number of pairs go four at once,
        // the rest one at a time, every sum in the points' order.
        std::size_t waiting[4];
        std::size_t n_waiting = 0;
        auto flush = [&] {
          for (std::size_t i = 0; i < n_waiting; ++i) {
            point_terms<kPlane, kPairNormals>(c, e_step, waiting[i], normals_local, r_local, &s);
          }
          n_waiting = 0;
        };
        for (std::size_t j = begin; j < end; ++j) {
          const std::size_t count = assoc.count[j];
          if (count == 0) continue;
          if (left_out != nullptr && left_out[j] != 0) {  // not in the solve: weight 0
            std::fill_n(&w_new[j * c.k], count, 0.0);
            continue;
          }
          if constexpr (kPairNormals) {
            if (four_points != nullptr && count <= kFourPointsMaxPairs) {
              if (n_waiting > 0 && assoc.count[waiting[0]] != count) flush();
              waiting[n_waiting++] = j;
              if (n_waiting == 4) {
                four_point_rows(c, e_step, waiting, count, *four_points, normals_local, r_local,
                                &s);
                n_waiting = 0;
              }
              continue;
            }
          }
          flush();
          point_terms<kPlane, kPairNormals>(c, e_step, j, normals_local, r_local, &s);
        }
        flush();
        blocks_[static_cast<std::size_t>(b)] = s;
      });
}

void NormalEquations::evaluate(const PointCloud& source, const PointCloud& target,
                               const AssociationTable& assoc, const WeightParams& weights,
                               const Eigen::Isometry3d& T, const double* w_prev, double* w_new,
                               double* r_sq, const Parallel* parallel, Evaluation* out,
                               const PlaneModel* plane, PairNormalMemo memo) {
  // Without r_sq the pass keeps a point's squared errors in a stack buffer of this size.
  assert(assoc.k <= AssociationTable::kMaxNeighbours);
  // The pass needs c and u only: no log-sum-exp (two logarithms per point). The error model
  // and the pair normals are template parameters of the pass (tags here), so that its per-pair
  // loops carry no model branches.
  const bool use_plane = plane != nullptr && plane->points != nullptr;
  const bool use_pair_normals = use_plane && plane->pair_source != nullptr;
  assert(source.size() <= blocks_.size() * kBlockSize);
  assert(!use_pair_normals ||
         pair_normals_.size() >= blocks_.size() * static_cast<std::size_t>(assoc.k));
  assert(!use_plane || use_pair_normals || plane->information != nullptr);
  // The pair normals' points four at a time (four_points.hpp) where the E-step's power is dyadic.
  DyadicStudentT dyadic;
  const bool four_points =
      use_pair_normals && four_points_ && weights.model == WeightModel::kStudentT &&
      dyadic_exponent(weights.dof, &dyadic.whole, &dyadic.eighths) && four_lanes_available();
  dyadic.dof = weights.dof;
  dyadic.inv_scale_sq = weights.inv_scale_sq;
  auto run = [&](const auto& e_step, auto kPlane, auto kPairNormals) {
    pass<decltype(kPlane)::value, decltype(kPairNormals)::value>(
        e_step, source, target, assoc, T, w_prev, w_new, r_sq, parallel, plane, memo,
        four_points ? &dyadic : nullptr);
  };
  with_weight_kernel<false>(weights.model, weights.dof, weights.inv_scale_sq,
                            [&](const auto& e_step) {
                              using Yes = std::true_type;
                              using No = std::false_type;
                              if (use_pair_normals) {
                                run(e_step, Yes(), Yes());
                              } else if (use_plane) {
                                run(e_step, Yes(), No());
                              } else {
                                run(e_step, No(), No());
                              }
                            });

  // Ordered reduction over blocks: independent of the thread count.
  const std::size_t n_blocks = block_count(source.size(), kBlockSize);
  double S0 = 0.0, cost = 0.0, cost_prev = 0.0;
  Eigen::Vector3d S1 = Eigen::Vector3d::Zero(), ebar = Eigen::Vector3d::Zero(),
                  ebar_cross_p = Eigen::Vector3d::Zero();
  Eigen::Matrix3d S2 = Eigen::Matrix3d::Zero();
  Matrix6d H = Matrix6d::Zero();
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const BlockSums& s = blocks_[b];
    S0 += s.S0;
    S1 += s.S1;
    S2 += s.S2;
    H += s.H;
    ebar += s.ebar;
    ebar_cross_p += s.ebar_cross_p;
    cost += s.cost;
    cost_prev += s.cost_prev;
  }
  out->cost = 0.5 * cost;
  out->cost_prev_weights = 0.5 * cost_prev;
  if (use_plane) {
    // Only the upper triangle was accumulated (add_plane_point): complete by symmetry.
    out->H = H.selfadjointView<Eigen::Upper>();
  } else {
    out->H.topLeftCorner<3, 3>() = S2.trace() * Eigen::Matrix3d::Identity() - S2;
    out->H.topRightCorner<3, 3>() = se3::skew(S1);
    out->H.bottomLeftCorner<3, 3>() = -se3::skew(S1);
    out->H.bottomRightCorner<3, 3>() = S0 * Eigen::Matrix3d::Identity();
  }
  out->weight_sum = S0;
  out->g.head<3>() = ebar_cross_p;
  out->g.tail<3>() = -ebar;
}

Matrix6d NormalEquations::normal_information(const PointCloud& source,
                                             const AssociationTable& assoc,
                                             const Eigen::Isometry3d& T, const double* w,
                                             const Buffer<PlanePoint>& target_points,
                                             const Parallel* parallel,
                                             std::vector<Matrix6d>* blocks) {
  const std::size_t k = static_cast<std::size_t>(assoc.k);
  const std::size_t n = source.size();
  blocks->resize(block_count(n, kBlockSize));
  // Upper blocks only (top left, top right, bottom right); the bottom left by symmetry below.
  parallel_for_blocks(parallel, n, kBlockSize,
                      [&](std::ptrdiff_t b, std::size_t begin, std::size_t end) {
                        Matrix6d H = Matrix6d::Zero();
                        for (std::size_t j = begin; j < end; ++j) {
                          const std::size_t slot = j * k;
                          Eigen::Matrix3d Obar = Eigen::Matrix3d::Zero();
                          if (!assoc.used(j)) continue;
                          for (std::size_t m = 0; m < assoc.count[j]; ++m) {
                            const Eigen::Vector3d& nk = target_points[assoc.index[slot + m]].n;
                            // No normal: every direction constrained (Omega = I).
                            if (nk.squaredNorm() > 0.0) {
                              Obar.noalias() += (w[slot + m] * nk) * nk.transpose();
                            } else {
                              Obar.diagonal().array() += w[slot + m];
                            }
                          }
                          const Eigen::Matrix3d P = se3::skew(T * source[j]);
                          H.topLeftCorner<3, 3>().noalias() -= P * Obar * P;
                          H.topRightCorner<3, 3>().noalias() += P * Obar;
                          H.bottomRightCorner<3, 3>() += Obar;
                        }
                        (*blocks)[static_cast<std::size_t>(b)] = H;
                      });
  Matrix6d H = Matrix6d::Zero();
  for (const Matrix6d& block : *blocks) H += block;
  H.bottomLeftCorner<3, 3>() = H.topRightCorner<3, 3>().transpose();
  return H;
}

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
