// four_points.cpp - see four_points.hpp. Only the functions here marked for AVX are compiled for
// it (a target attribute, not a flag of the file), as in four_lanes.cpp.
#include "model/four_points.hpp"

#include <cfloat>

#include "model/avx_power.hpp"
#include "model/four_lanes.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

#if PPCR_AVX_KERNELS

namespace {

// Four rows (a_l, b_l, c_l, d_l) of four doubles as four columns: col0 = (a_0, a_1, a_2, a_3)...
PPCR_AVX inline void transpose(__m256d r0, __m256d r1, __m256d r2, __m256d r3, __m256d* c0,
                               __m256d* c1, __m256d* c2, __m256d* c3) {
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1);  // a0 a1 c0 c1
  const __m256d t1 = _mm256_unpackhi_pd(r0, r1);  // b0 b1 d0 d1
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3);  // a2 a3 c2 c3
  const __m256d t3 = _mm256_unpackhi_pd(r2, r3);  // b2 b3 d2 d3
  *c0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  *c1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  *c2 = _mm256_permute2f128_pd(t0, t2, 0x31);
  *c3 = _mm256_permute2f128_pd(t1, t3, 0x31);
}

// Coordinate `axis` of each row's vector `field`, a lane per row.
PPCR_AVX inline __m256d lanes(const FourPointRow rows[4], Eigen::Vector3d FourPointRow::*field,
                              int axis) {
  return _mm256_setr_pd((rows[0].*field)[axis], (rows[1].*field)[axis], (rows[2].*field)[axis],
                        (rows[3].*field)[axis]);
}

// (x_a y_a + x_b y_b) + x_c y_c, dot_in_order's order (pair_normals.hpp), lane by lane.
PPCR_AVX inline __m256d dot3(__m256d xa, __m256d xb, __m256d xc, __m256d ya, __m256d yb,
                             __m256d yc) {
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(xa, ya), _mm256_mul_pd(xb, yb)),
                       _mm256_mul_pd(xc, yc));
}

// mask ? b : a, lane by lane, for a mask of a comparison (all bits set or none): bitwise, since
// GCC 12 (the version measured) takes a blend for AVX alone apart into scalar branches.
PPCR_AVX inline __m256d select(__m256d mask, __m256d b, __m256d a) {
  return _mm256_or_pd(_mm256_and_pd(mask, b), _mm256_andnot_pd(mask, a));
}

// a b - c d
PPCR_AVX inline __m256d difference_of_products(__m256d a, __m256d b, __m256d c, __m256d d) {
  return _mm256_sub_pd(_mm256_mul_pd(a, b), _mm256_mul_pd(c, d));
}

// acc + a * b
PPCR_AVX inline __m256d add_product(__m256d acc, __m256d a, __m256d b) {
  return _mm256_add_pd(acc, _mm256_mul_pd(a, b));
}

// Per pair slot m, the four rows' values in lanes, kept from step to step: the pair normals s, the
// errors e = y - p, s's q = 1 / |s|^2 (0 without a normal), s . e, and the squared error r, which
// the E-step overwrites with u.
struct PairLanes {
  __m256d sx[kFourPointsMaxPairs], sy[kFourPointsMaxPairs], sz[kFourPointsMaxPairs];
  __m256d ex[kFourPointsMaxPairs], ey[kFourPointsMaxPairs], ez[kFourPointsMaxPairs];
  __m256d qs[kFourPointsMaxPairs], se[kFourPointsMaxPairs], rs[kFourPointsMaxPairs];
};

// The weighted sums over a row's pairs (accumulate_pair_normals), over c: Obar / c = A I + N,
// ebar / c = b, U = sum u, ur = sum u r.
struct PairSums {
  __m256d A, U, ur, n00, n11, n01, n12, n02, n22, bx, by, bz;
};

// 1. Pair normals (pair_normals.cpp) and squared errors (squared_errors, normal_equations.cpp);
// returns each row's smallest squared error.
PPCR_AVX __m256d pair_errors(const FourPointRow rows[4], std::size_t count,
                             const PlanePoint* points, double epsilon, PairNormalMode mode,
                             PairLanes* t) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d sign_bit = _mm256_set1_pd(-0.0);
  const __m256d eps = _mm256_set1_pd(epsilon);
  const __m256d px = lanes(rows, &FourPointRow::p_target, 0);
  const __m256d py = lanes(rows, &FourPointRow::p_target, 1);
  const __m256d pz = lanes(rows, &FourPointRow::p_target, 2);
  const __m256d mx = lanes(rows, &FourPointRow::normal_target, 0);
  const __m256d my = lanes(rows, &FourPointRow::normal_target, 1);
  const __m256d mz = lanes(rows, &FourPointRow::normal_target, 2);
  __m256d r_min = zero;
  for (std::size_t m = 0; m < count; ++m) {
    const PlanePoint* record[4] = {&points[rows[0].idx[m]], &points[rows[1].idx[m]],
                                   &points[rows[2].idx[m]], &points[rows[3].idx[m]]};
    __m256d yx, yy, yz, unused, nx, ny, nz;
    transpose(_mm256_loadu_pd(record[0]->y.data()), _mm256_loadu_pd(record[1]->y.data()),
              _mm256_loadu_pd(record[2]->y.data()), _mm256_loadu_pd(record[3]->y.data()), &yx, &yy,
              &yz, &unused);
    transpose(_mm256_loadu_pd(record[0]->n.data()), _mm256_loadu_pd(record[1]->n.data()),
              _mm256_loadu_pd(record[2]->n.data()), _mm256_loadu_pd(record[3]->n.data()), &nx, &ny,
              &nz, &unused);
    __m256d sign, q, no_normal;  // sign: the flip in the sign bit; no_normal: s = 0
    if (mode == PairNormalMode::kFromMemo) {
      const __m256d memo =
          _mm256_setr_pd(rows[0].memo[m], rows[1].memo[m], rows[2].memo[m], rows[3].memo[m]);
      sign = _mm256_and_pd(memo, sign_bit);
      q = _mm256_andnot_pd(sign_bit, memo);
      no_normal = _mm256_cmp_pd(q, zero, _CMP_EQ_OQ);
    } else {
      // s = n + sign(n . m) m, flipped when !(n . m >= 0); a zero n gives s = 0, no flip.
      no_normal = _mm256_cmp_pd(dot3(nx, ny, nz, nx, ny, nz), zero, _CMP_EQ_OQ);
      const __m256d flip = _mm256_andnot_pd(
          no_normal, _mm256_cmp_pd(dot3(nx, ny, nz, mx, my, mz), zero, _CMP_NGE_UQ));
      sign = _mm256_and_pd(flip, sign_bit);
    }
    t->sx[m] = _mm256_andnot_pd(no_normal, _mm256_add_pd(nx, _mm256_xor_pd(mx, sign)));
    t->sy[m] = _mm256_andnot_pd(no_normal, _mm256_add_pd(ny, _mm256_xor_pd(my, sign)));
    t->sz[m] = _mm256_andnot_pd(no_normal, _mm256_add_pd(nz, _mm256_xor_pd(mz, sign)));
    if (mode != PairNormalMode::kFromMemo) {
      const __m256d sq = dot3(t->sx[m], t->sy[m], t->sz[m], t->sx[m], t->sy[m], t->sz[m]);
      q = _mm256_and_pd(_mm256_cmp_pd(sq, zero, _CMP_GT_OQ), _mm256_div_pd(one, sq));
      if (mode == PairNormalMode::kFill) {
        alignas(32) double memo[4];
        _mm256_store_pd(memo, _mm256_or_pd(q, sign));  // q with the flip in its sign bit
        for (int l = 0; l < 4; ++l) rows[l].memo[m] = memo[l];
      }
    }
    t->qs[m] = q;
    t->ex[m] = _mm256_sub_pd(yx, px);
    t->ey[m] = _mm256_sub_pd(yy, py);
    t->ez[m] = _mm256_sub_pd(yz, pz);
    t->se[m] = dot3(t->sx[m], t->sy[m], t->sz[m], t->ex[m], t->ey[m], t->ez[m]);
    const __m256d a = select(_mm256_cmp_pd(q, zero, _CMP_GT_OQ), eps, one);
    const __m256d r = _mm256_add_pd(
        _mm256_mul_pd(a, dot3(t->ex[m], t->ey[m], t->ez[m], t->ex[m], t->ey[m], t->ez[m])),
        _mm256_mul_pd(q, _mm256_mul_pd(t->se[m], t->se[m])));
    t->rs[m] = r;
    r_min = m == 0 ? r : select(_mm256_cmp_pd(r, r_min, _CMP_LT_OQ), r, r_min);
  }
  return r_min;
}

// 2. E-step (e_step_kernel.hpp, student_t_weights): u_k = p_k q_k replaces r_k in t->rs; each
// row's c and sum u r. Writes the rows' squared errors and adds w_prev . r to sums->cost_prev
// first. Returns false, having written nothing, when a row's errors all overflow.
PPCR_AVX bool student_t_lanes(const FourPointRow rows[4], std::size_t count,
                              const DyadicStudentT& e_step, __m256d r_min, PairLanes* t,
                              BlockSums* sums, __m256d* c_out, __m256d* ur_out) {
  __m256d* rs = t->rs;
  const __m256d zero = _mm256_setzero_pd();
  const __m256d inv = _mm256_set1_pd(e_step.inv_scale_sq);
  const __m256d z_min = _mm256_mul_pd(r_min, inv);
  if (_mm256_movemask_pd(_mm256_cmp_pd(z_min, _mm256_set1_pd(DBL_MAX), _CMP_GT_OQ)) != 0) {
    return false;  // a row's errors all overflow: the one-point kernels take it
  }
  alignas(32) double r_lanes[kFourPointsMaxPairs][4];
  for (std::size_t m = 0; m < count; ++m) _mm256_store_pd(r_lanes[m], rs[m]);
  double prev = sums->cost_prev;
  for (int l = 0; l < 4; ++l) {
    if (rows[l].r_sq != nullptr) {
      for (std::size_t m = 0; m < count; ++m) rows[l].r_sq[m] = r_lanes[m][l];
    }
    if (rows[l].w_prev != nullptr) {  // read before any weight is written (w_prev may be w)
      for (std::size_t m = 0; m < count; ++m) prev += rows[l].w_prev[m] * r_lanes[m][l];
    }
  }
  sums->cost_prev = prev;
  const __m256d dof = _mm256_set1_pd(e_step.dof);
  const __m256d nu_z_min = _mm256_add_pd(dof, z_min);
  __m256d sum = zero;
  __m256d* u = rs;  // u_k replaces r_k, read in its step's sum first
  __m256d ur = zero;
  for (std::size_t m = 0; m < count; ++m) {
    const __m256d ratio =
        _mm256_div_pd(nu_z_min, _mm256_add_pd(dof, _mm256_mul_pd(rs[m], inv)));  // q_k
    const __m256d power = dyadic_power(ratio, e_step.whole, e_step.eighths);     // q_k^e
    sum = _mm256_add_pd(sum, power);
    const __m256d um = _mm256_mul_pd(power, ratio);
    ur = add_product(ur, um, rs[m]);  // accumulate_pair_normals' sum u r, in its order
    u[m] = um;
  }
  // c = (nu + 3) / ((nu + z_min) sum), in two divisions where the product overflows, as the
  // scalar kernel (student_t_weights).
  const __m256d nu_3 = _mm256_set1_pd(e_step.dof + 3.0);
  const __m256d denominator = _mm256_mul_pd(nu_z_min, sum);
  const __m256d finite = _mm256_cmp_pd(denominator, _mm256_set1_pd(DBL_MAX), _CMP_LE_OQ);
  __m256d c = _mm256_div_pd(nu_3, denominator);
  if (_mm256_movemask_pd(finite) != 0xF) {
    c = select(finite, c, _mm256_div_pd(_mm256_div_pd(nu_3, nu_z_min), sum));
  }
  *c_out = c;
  *ur_out = ur;
  return true;
}

// 3. The sums over each row's pairs, and its weights w = c u.
PPCR_AVX PairSums pair_sums(const FourPointRow rows[4], std::size_t count, double epsilon,
                            __m256d c, __m256d ur, const PairLanes& t) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d eps = _mm256_set1_pd(epsilon);
  const __m256d* u = t.rs;
  const __m256d* qs = t.qs;
  const __m256d *sx = t.sx, *sy = t.sy, *sz = t.sz, *ex = t.ex, *ey = t.ey, *ez = t.ez;
  const __m256d* se = t.se;
  __m256d A = zero, U = zero, n00 = zero, n11 = zero, n01 = zero, n12 = zero, n02 = zero,
          n22 = zero, bx = zero, by = zero, bz = zero;
  alignas(32) double w_lanes[kFourPointsMaxPairs][4];
  for (std::size_t m = 0; m < count; ++m) {
    const __m256d um = u[m];
    const __m256d a = select(_mm256_cmp_pd(qs[m], zero, _CMP_GT_OQ), eps, one);
    const __m256d ua = _mm256_mul_pd(um, a);
    const __m256d uq = _mm256_mul_pd(um, qs[m]);
    const __m256d une = _mm256_mul_pd(uq, se[m]);
    const __m256d unx = _mm256_mul_pd(uq, sx[m]);
    const __m256d uny = _mm256_mul_pd(uq, sy[m]);
    const __m256d unz = _mm256_mul_pd(uq, sz[m]);
    A = _mm256_add_pd(A, ua);
    U = _mm256_add_pd(U, um);
    n00 = add_product(n00, unx, sx[m]);
    n11 = add_product(n11, uny, sy[m]);
    n01 = add_product(n01, unx, sy[m]);
    n12 = add_product(n12, uny, sz[m]);
    n02 = add_product(n02, unx, sz[m]);
    n22 = add_product(n22, unz, sz[m]);
    bx = _mm256_add_pd(bx, _mm256_add_pd(_mm256_mul_pd(ua, ex[m]), _mm256_mul_pd(une, sx[m])));
    by = _mm256_add_pd(by, _mm256_add_pd(_mm256_mul_pd(ua, ey[m]), _mm256_mul_pd(une, sy[m])));
    bz = _mm256_add_pd(bz, _mm256_add_pd(_mm256_mul_pd(ua, ez[m]), _mm256_mul_pd(une, sz[m])));
    _mm256_store_pd(w_lanes[m], _mm256_mul_pd(um, c));
  }
  for (int l = 0; l < 4; ++l) {
    for (std::size_t m = 0; m < count; ++m) rows[l].w[m] = w_lanes[m][l];
  }
  return PairSums{A, U, ur, n00, n11, n01, n12, n02, n22, bx, by, bz};
}

// 4. The rows' terms of H and g (add_plane_point, normal_equations.cpp), formed in lanes, then
// added to the block's sums row by row: each sum in the rows' order, as one row at a time.
PPCR_AVX void add_row_terms(const FourPointRow rows[4], __m256d c, const PairSums& p,
                            BlockSums* sums) {
  const __m256d px = lanes(rows, &FourPointRow::p_target, 0);
  const __m256d py = lanes(rows, &FourPointRow::p_target, 1);
  const __m256d pz = lanes(rows, &FourPointRow::p_target, 2);
  const __m256d oxx = _mm256_mul_pd(c, _mm256_add_pd(p.n00, p.A));
  const __m256d oyy = _mm256_mul_pd(c, _mm256_add_pd(p.n11, p.A));
  const __m256d ozz = _mm256_mul_pd(c, _mm256_add_pd(p.n22, p.A));
  const __m256d oxy = _mm256_mul_pd(c, p.n01);
  const __m256d oyz = _mm256_mul_pd(c, p.n12);
  const __m256d oxz = _mm256_mul_pd(c, p.n02);
  const __m256d ebx = _mm256_mul_pd(c, p.bx);
  const __m256d eby = _mm256_mul_pd(c, p.by);
  const __m256d ebz = _mm256_mul_pd(c, p.bz);
  // M = [p]_x Obar, column by column: p x (column of Obar); Eigen's cross product, component by
  // component: (a_y b_z - a_z b_y, a_z b_x - a_x b_z, a_x b_y - a_y b_x).
  const __m256d M00 = difference_of_products(py, oxz, pz, oxy);
  const __m256d M10 = difference_of_products(pz, oxx, px, oxz);
  const __m256d M20 = difference_of_products(px, oxy, py, oxx);
  const __m256d M01 = difference_of_products(py, oyz, pz, oyy);
  const __m256d M11 = difference_of_products(pz, oxy, px, oyz);
  const __m256d M21 = difference_of_products(px, oyy, py, oxy);
  const __m256d M02 = difference_of_products(py, ozz, pz, oyz);
  const __m256d M12 = difference_of_products(pz, oxz, px, ozz);
  const __m256d M22 = difference_of_products(px, oyz, py, oxz);
  // The rest of a row's terms, one lane per row: the top-left block's upper triangle (row 0 is
  // p x (row 0 of M); (1,1), (1,2), (2,2) from rows 1 and 2 of M, as add_plane_point writes
  // them), Obar's three entries below row 3, ebar, ebar x p, the cost and the weight.
  constexpr int kTerms = 17;
  alignas(32) double lanes[kTerms][4];
  const __m256d terms[kTerms] = {difference_of_products(py, M02, pz, M01),
                                 difference_of_products(pz, M00, px, M02),
                                 difference_of_products(px, M01, py, M00),
                                 difference_of_products(pz, M10, px, M12),
                                 difference_of_products(px, M11, py, M10),
                                 difference_of_products(px, M21, py, M20),
                                 oyy,
                                 oyz,
                                 ozz,
                                 ebx,
                                 eby,
                                 ebz,
                                 difference_of_products(eby, pz, ebz, py),
                                 difference_of_products(ebz, px, ebx, pz),
                                 difference_of_products(ebx, py, eby, px),
                                 _mm256_mul_pd(c, p.ur),
                                 _mm256_mul_pd(c, p.U)};
  for (int i = 0; i < kTerms; ++i) _mm256_store_pd(lanes[i], terms[i]);
  // Columns 3-5 of H hold M and Obar's first row contiguously (column-major): (M_0c, M_1c, M_2c,
  // Obar_0c) at H(0, 3 + c), a row's four added as one vector.
  __m256d column[3][4];
  transpose(M00, M10, M20, oxx, &column[0][0], &column[0][1], &column[0][2], &column[0][3]);
  transpose(M01, M11, M21, oxy, &column[1][0], &column[1][1], &column[1][2], &column[1][3]);
  transpose(M02, M12, M22, oxz, &column[2][0], &column[2][1], &column[2][2], &column[2][3]);
  Matrix6d& H = sums->H;
  for (int l = 0; l < 4; ++l) {  // row after row
    for (int col = 0; col < 3; ++col) {
      double* h = &H(0, 3 + col);
      _mm256_storeu_pd(h, _mm256_add_pd(_mm256_loadu_pd(h), column[col][l]));
    }
    H(0, 0) += lanes[0][l];
    H(0, 1) += lanes[1][l];
    H(0, 2) += lanes[2][l];
    H(1, 1) += lanes[3][l];
    H(1, 2) += lanes[4][l];
    H(2, 2) += lanes[5][l];
    H(4, 4) += lanes[6][l];
    H(4, 5) += lanes[7][l];
    H(5, 5) += lanes[8][l];
    sums->ebar.x() += lanes[9][l];
    sums->ebar.y() += lanes[10][l];
    sums->ebar.z() += lanes[11][l];
    sums->ebar_cross_p.x() += lanes[12][l];
    sums->ebar_cross_p.y() += lanes[13][l];
    sums->ebar_cross_p.z() += lanes[14][l];
    sums->cost += lanes[15][l];
    sums->S0 += lanes[16][l];
  }
}

}  // namespace

PPCR_AVX bool four_point_terms(const FourPointRow rows[4], std::size_t count,
                               const PlanePoint* points, double epsilon, PairNormalMode mode,
                               const DyadicStudentT& e_step_params, BlockSums* sums) {
  PairLanes t;
  const __m256d r_min = pair_errors(rows, count, points, epsilon, mode, &t);
  __m256d c, ur;
  if (!student_t_lanes(rows, count, e_step_params, r_min, &t, sums, &c, &ur)) return false;
  add_row_terms(rows, c, pair_sums(rows, count, epsilon, c, ur, t), sums);
  return true;
}

#else

bool four_point_terms(const FourPointRow*, std::size_t, const PlanePoint*, double, PairNormalMode,
                      const DyadicStudentT&, BlockSums*) {
  return false;
}

#endif

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
