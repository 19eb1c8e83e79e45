// four_points.hpp - the plane pass's per-point terms with pair normals (normal_equations.cpp),
// four source points at a time in AVX lanes, on x86-64 CPUs with AVX, chosen at run time.
//
// A lane is a source point: it runs, pair by pair in the point's order, the one-point pass's
// operations (pair_normals.cpp, the squared errors and accumulate_pair_normals in
// normal_equations.cpp, the Student-t E-step of e_step_kernel.hpp with a dyadic power): each
// addition, product, division and square root correctly rounded (IEEE 754) whatever the vector
// width, none contracted (-ffp-contract=off), every sum in its scalar order. So every output is
// the same to the bit as the one-point path's (tests/core/test_normal_equations.cpp; a NaN's
// sign and payload aside: the library drops non-finite points). Why: the
// one-point path takes a point's pairs one or two at a time, and its gathers, divisions and
// roots leave most of the vector width unused (docs/PERFORMANCE.md, "Four points at a time").
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "model/normal_equations.hpp"
#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

/// The Student-t E-step whose power q^e has 8e an integer (e_step_kernel.hpp, PowerDyadic, and
/// PowerFour: e = 4 gives the same bits).
struct DyadicStudentT {
  int whole = 0;    // floor(e)
  int eighths = 0;  // (e - floor(e)) * 8
  double dof = 0.0;
  double inv_scale_sq = 1.0;
};

/// How a pass forms the pair normals (PairNormalMemo): afresh, afresh and kept, or from the memo.
enum class PairNormalMode { kFresh, kFill, kFromMemo };

/// One source point of the four: its inputs, and where its outputs go.
struct FourPointRow {
  Eigen::Vector3d p_target;       // T x_j: the point in the target frame
  Eigen::Vector3d normal_target;  // R m_j: its source normal at the association's rotation
  const std::uint32_t* idx;       // its count target indices
  const double* w_prev;           // null, or its count previous weights
  double* memo;                   // its count memo slots (kFill, kFromMemo), else unused
  double* r_sq;                   // null, or room for its count squared errors
  double* w;                      // its count weights, written
};

/// The most pairs per point the four-point path takes (its stack holds them).
constexpr std::size_t kFourPointsMaxPairs = 16;

/// The four rows' pair normals, squared errors, E-step weights and terms of H, g and the costs,
/// each row with `count` pairs (1 <= count <= kFourPointsMaxPairs), added to *sums as the
/// one-point path adds them, row after row (w_prev . r to cost_prev for rows with w_prev).
/// Returns false, having written no weight, squared error or sum (with kFill the memo may be
/// written: the one-point path writes the same), when a row's every error overflows
/// (e_step_kernel.hpp): the caller takes the rows one at a time then. Only when
/// four_lanes_available() (four_lanes.hpp).
bool four_point_terms(const FourPointRow rows[4], std::size_t count, const PlanePoint* points,
                      double epsilon, PairNormalMode mode, const DyadicStudentT& e_step,
                      BlockSums* sums);

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
