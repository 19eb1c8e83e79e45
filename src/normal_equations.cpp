// normal_equations.cpp - fused residuals / weights / normal equations pass (see header).
#include "normal_equations.hpp"

#include <cassert>
#include <cstdint>
#include <type_traits>

#include "parallel.hpp"
#include "ppcr/se3.hpp"
#include "weight_kernel.hpp"

namespace ppcr {
namespace detail {
namespace {

// Omega = a I + n n^T of a target point (error_model.hpp): a = epsilon with a normal, else 1.
inline double omega_isotropic(const Eigen::Vector3d& n, double epsilon) {
  return n.squaredNorm() > 0.0 ? epsilon : 1.0;
}

}  // namespace

void pack_plane_points(const PointCloud& target, const std::vector<Eigen::Vector3d>& normals,
                       double epsilon, std::vector<PlanePoint>* out) {
  out->resize(target.size());
  for (std::size_t i = 0; i < target.size(); ++i) {
    PlanePoint& q = (*out)[i];
    q.y = target[i];
    q.n = normals[i];
    q.a = omega_isotropic(normals[i], epsilon);
  }
}

void NormalEquations::resize(std::size_t source_points) {
  blocks_.resize((source_points + kBlockSize - 1) / kBlockSize);
}

template <bool kPlane, bool kPairNormals, class Kernel>
void NormalEquations::pass(const Kernel& e_step, const PointCloud& source, const PointCloud& target,
                           const AssociationTable& assoc, const Eigen::Isometry3d& T,
                           const double* w_prev, double* w_new, double* r_sq, int num_threads,
                           const PlaneModel* plane) {
  const std::size_t n = source.size();
  const std::size_t k = static_cast<std::size_t>(assoc.k);
  const std::size_t n_blocks = (n + kBlockSize - 1) / kBlockSize;
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d t = T.translation();
  const PlanePoint* points = kPlane ? plane->points->data() : nullptr;
  // Per-slot pair normals (source normals on) replace the target points' normals.
  // (kPairNormals: a template parameter, so that the per-pair choice is compiled out.)
  const Eigen::Vector3d* pair_normals = kPairNormals ? plane->pair_normals->data() : nullptr;
  const double epsilon = kPlane ? plane->epsilon : 1.0;

  parallel_for(num_threads, static_cast<std::ptrdiff_t>(n_blocks), [&](std::ptrdiff_t b) {
    // Without r_sq, a point's squared errors live on the stack (read back within the point).
    double r_local[AssociationTable::kMaxNeighbours];
    BlockSums s;
    s.S0 = s.cost = s.cost_prev = 0.0;
    s.S1.setZero();
    s.ebar.setZero();
    s.ebar_cross_p.setZero();
    s.S2.setZero();
    s.H.setZero();
    const std::size_t begin = static_cast<std::size_t>(b) * kBlockSize;
    const std::size_t end = std::min(n, begin + kBlockSize);
    for (std::size_t j = begin; j < end; ++j) {
      const std::size_t count = assoc.count[j];
      if (count == 0) continue;
      const std::size_t slot = j * k;
      const std::uint32_t* idx = &assoc.index[slot];
      double* r = r_sq != nullptr ? &r_sq[slot] : r_local;
      double* w = &w_new[slot];
      const Eigen::Vector3d p = R * source[j] + t;
      // Squared errors of the point's pairs (Mahalanobis for the plane model), and the cost
      // under the previous weights.
      if constexpr (kPlane) {
        for (std::size_t m = 0; m < count; ++m) {
          const PlanePoint& q = points[idx[m]];
          const Eigen::Vector3d e = q.y - p;
          if constexpr (kPairNormals) {
            const Eigen::Vector3d& nk = pair_normals[slot + m];
            const double ne = nk.dot(e);
            r[m] = omega_isotropic(nk, epsilon) * e.squaredNorm() + ne * ne;
          } else {
            const double ne = q.n.dot(e);
            r[m] = q.a * e.squaredNorm() + ne * ne;
          }
        }
      } else {
        for (std::size_t m = 0; m < count; ++m) r[m] = (target[idx[m]] - p).squaredNorm();
      }
      if (w_prev != nullptr) {  // read before the E-step writes w (w_prev may be w_new)
        const double* wp = &w_prev[slot];
        for (std::size_t m = 0; m < count; ++m) s.cost_prev += wp[m] * r[m];
      }
      // E-step at this pose (eq. 2-4): w = c * u.
      const PointWeights pw = e_step(r, count, w);
      if constexpr (kPlane) {
        // Obar = c (A I + N), N = sum_k u_k n_k n_k^T (symmetric: 6 sums),
        // ebar = c sum_k u_k (a_k e_k + n_k (n_k . e_k)).
        // The sums are kept in pairs of lanes (Eigen::Array2d: one SSE2 / NEON operation for
        // two). Each lane does one sum's scalar operations in the scalar order (n . e as
        // (x + y) + z), so every sum is the same to the bit as when written one by one: the
        // benchmark sets' per-iteration traces were identical before and after this form. (On
        // x86-64 as built by default, without FMA; where the compiler contracts a * b + c into
        // fused multiply-adds, e.g. AArch64 or -march=native, it may fuse either form
        // differently.)
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
          const Eigen::Vector3d& nk = kPairNormals ? pair_normals[slot + m] : q.n;
          const double ak = kPairNormals ? omega_isotropic(nk, epsilon) : q.a;
          const Eigen::Array2d n_xy = Eigen::Map<const Eigen::Array2d>(nk.data());
          const Eigen::Array2d n_yz = Eigen::Map<const Eigen::Array2d>(nk.data() + 1);
          const double nz = nk.z();
          const Eigen::Array2d e_xy = Eigen::Map<const Eigen::Array2d>(q.y.data()) - p_xy;
          const double ez = q.y.z() - p.z();
          const Eigen::Array2d ne_xy = n_xy * e_xy;
          const double ua = u * ak;
          const double une = u * (ne_xy[0] + ne_xy[1] + nz * ez);  // u (n . e)
          const Eigen::Array2d un_xy = u * n_xy;
          const double unz = u * nz;
          AU += Eigen::Array2d(ua, u);
          ur += u * r[m];
          n00_n11 += un_xy * n_xy;
          n01_n12 += un_xy * n_yz;
          n02_n22 += Eigen::Array2d(un_xy[0], unz) * nz;
          bxy += ua * e_xy + une * n_xy;
          bz += ua * ez + une * nz;
          w[m] *= pw.c;
        }
        const double A = AU[0], U = AU[1];
        const double n00 = n00_n11[0], n11 = n00_n11[1], n01 = n01_n12[0], n12 = n01_n12[1];
        const double n02 = n02_n22[0], n22 = n02_n22[1], bx = bxy[0], by = bxy[1];
        Eigen::Matrix3d Obar;
        Obar << n00 + A, n01, n02, n01, n11 + A, n12, n02, n12, n22 + A;
        Obar *= pw.c;
        const Eigen::Vector3d ebar = pw.c * Eigen::Vector3d(bx, by, bz);
        const Eigen::Matrix3d P = se3::skew(p);
        const Eigen::Matrix3d PO = P * Obar;  // [p]_x Obar
        s.H.topLeftCorner<3, 3>().noalias() -= PO * P;
        s.H.topRightCorner<3, 3>() += PO;
        s.H.bottomRightCorner<3, 3>() += Obar;
        s.ebar += ebar;
        s.ebar_cross_p += ebar.cross(p);
        s.cost += pw.c * ur;
        s.S0 += pw.c * U;
      } else {
        // W_j, sum_k w y_k and the cost, accumulated with u and scaled by c once.
        double U = 0.0, ur = 0.0;
        Eigen::Vector3d uy = Eigen::Vector3d::Zero();
        for (std::size_t m = 0; m < count; ++m) {
          U += w[m];
          ur += w[m] * r[m];
          uy += w[m] * target[idx[m]];
          w[m] *= pw.c;
        }
        const double W = pw.c * U;
        const Eigen::Vector3d ebar = pw.c * uy - W * p;  // sum_k w_kj e_kj
        s.cost += pw.c * ur;
        s.S0 += W;
        s.S1 += W * p;
        s.S2.noalias() += (W * p) * p.transpose();
        s.ebar += ebar;
        s.ebar_cross_p += ebar.cross(p);  // [p]_x^T ebar = ebar x p
      }
    }
    blocks_[static_cast<std::size_t>(b)] = s;
  });
}

void NormalEquations::evaluate(const PointCloud& source, const PointCloud& target,
                               const AssociationTable& assoc, const WeightParams& weights,
                               const Eigen::Isometry3d& T, const double* w_prev, double* w_new,
                               double* r_sq, int num_threads, Evaluation* out,
                               const PlaneModel* plane) {
  // Without r_sq the pass keeps a point's squared errors in a stack buffer of this size.
  assert(assoc.k <= AssociationTable::kMaxNeighbours);
  // The pass needs c and u only: no log-sum-exp (two logarithms per point). The error model
  // and the pair normals are template parameters of the pass (tags here), so that its per-pair
  // loops carry no model branches.
  const bool use_plane = plane != nullptr && plane->points != nullptr;
  const bool use_pair_normals = use_plane && plane->pair_normals != nullptr;
  auto run = [&](const auto& e_step, auto kPlane, auto kPairNormals) {
    pass<decltype(kPlane)::value, decltype(kPairNormals)::value>(
        e_step, source, target, assoc, T, w_prev, w_new, r_sq, num_threads, plane);
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
  const std::size_t n_blocks = (source.size() + kBlockSize - 1) / kBlockSize;
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
    // Only the top-right block was accumulated off the diagonal: complete by symmetry.
    H.bottomLeftCorner<3, 3>() = H.topRightCorner<3, 3>().transpose();
    out->H = H;
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
                                             const std::vector<PlanePoint>& target_points) {
  Matrix6d H = Matrix6d::Zero();
  const std::size_t k = static_cast<std::size_t>(assoc.k);
  for (std::size_t j = 0; j < source.size(); ++j) {
    const std::size_t slot = j * k;
    Eigen::Matrix3d Obar = Eigen::Matrix3d::Zero();
    for (std::size_t m = 0; m < assoc.count[j]; ++m) {
      const Eigen::Vector3d& nk = target_points[assoc.index[slot + m]].n;
      // A target point without a normal constrains all directions (Omega = I).
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
  H.bottomLeftCorner<3, 3>() = H.topRightCorner<3, 3>().transpose();
  return H;
}

}  // namespace detail
}  // namespace ppcr
