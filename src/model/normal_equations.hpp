// normal_equations.hpp - one pass over the associations at a pose: residuals, E-step weights,
// costs, and the Gauss-Newton system H delta = -g of the weighted cost.
//
// With the twist delta = (omega, v) applied on the left (se3.hpp), the error of pair (j, k) is
// e_kj = y_k - p_j, p_j = T x_j, and its Jacobian  J_j = [ [p_j]_x | -I ]  is the same for every
// neighbour k of source point j. So, with W_j = sum_k w_kj and
// ebar_j = sum_k w_kj e_kj = sum_k w_kj y_k - W_j p_j,
//   H = sum_j W_j J_j^T J_j,   g = sum_j J_j^T ebar_j,   cost = 1/2 sum_kj w_kj |e_kj|^2.
// Expanding J_j^T J_j = [ |p|^2 I - p p^T , [p]_x ; -[p]_x , I ] shows H depends on the source
// points only through S0 = sum W_j, S1 = sum W_j p_j and S2 = sum W_j p_j p_j^T:
//   H = [ tr(S2) I - S2 , [S1]_x ; -[S1]_x , S0 I ],   g = [ sum ebar_j x p_j ; -sum ebar_j ].
// So each source point adds 16 numbers, not a 6x6 outer product per pair.
//
// Plane model (ppcr/options.hpp, ErrorModel): r_kj = e^T Omega_k e with Omega_k = a_k I + n_k n_k^T
// (a_k = epsilon with a normal, 1 without); with source normals n_k is the pair's normal n_kj,
// a constant of the pass, so the same formulas hold with Omega_kj. J_j is still shared by a point's
// neighbours, so with Obar_j = sum_k w_kj Omega_k and ebar_j = sum_k w_kj Omega_k e_kj:
//   H = sum_j J_j^T Obar_j J_j = sum_j [ -[p]_x Obar [p]_x , [p]_x Obar ; -Obar [p]_x , Obar ],
//   g = sum_j [ ebar_j x p_j ; -ebar_j ]:  one 6x6 term per source point.
//
// Reduction: source points are cut into fixed blocks of kBlockSize (independent of the thread
// count); each block is summed serially into its own slot, then the slots are summed in order.
// The result is bit-identical whatever the number of threads.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "association/association_table.hpp"
#include "common/buffer.hpp"
#include "model/e_step.hpp"
#include "ppcr/abi.hpp"
#include "ppcr/options.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace detail {

class Parallel;         // parallel.hpp
struct DyadicStudentT;  // four_points.hpp

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// The E-step's parameters; model and dof default to the options' (options.hpp).
struct WeightParams {
  WeightModel model = ExpertOptions{}.weight_model;
  double dof = RegistrationOptions{}.dof;
  double inv_scale_sq = 1.0;  // 1 / s^2
};

/// One target point of the plane model in one cache line, gathered by the pass with one random
/// access per pair: what the squared error r = a |e|^2 + (n . e)^2 needs (and the pair normals,
/// normal_information and the alignment measures read), and b_z of PlaneInformation.
struct alignas(64) PlanePoint {
  Eigen::Vector3d y;  // position (the target cloud's point)
  double a;           // Omega = a I + n n^T: a = epsilon with a normal, 1 without
  Eigen::Vector3d n;  // unit normal, or zero for "no normal"
  double b_z;         // b = Omega y (z; x and y in PlaneInformation)
};
static_assert(sizeof(PlanePoint) == 64, "PlanePoint: one cache line");

/// The rest of a target point's Omega = a I + n n^T and b = Omega y, fixed per target point, for
/// the pass with the target's normals (not with pair normals, which form Omega per pair): it sums
///   Obar_j / c = sum_k u_k Omega_k   and   ebar_j / c = sum_k u_k b_k - (Obar_j / c) p_j
/// (ebar_j = sum_k w_kj Omega_k (y_k - p_j)) with one product and sum per pair of numbers instead
/// of forming Omega_k e_kj from n_k and e_kj per pair. The cost of that form: each term of ebar_j
/// rounds by about eps |y_k| instead of eps |e_kj|, i.e. the step by about eps |y|, the resolution
/// of the (centred) coordinates themselves (docs/PERFORMANCE.md). Kept apart from PlanePoint so
/// that the pair normals' pass (the default) holds and reads one cache line per target point.
struct alignas(64) PlaneInformation {
  // Omega's six entries and (b_x, b_y), in the pass's pairs of lanes.
  double omega_xx_yy[2], omega_xy_yz[2], omega_xz_zz[2], b_xy[2];
};
static_assert(sizeof(PlaneInformation) == 64, "PlaneInformation: one cache line");

/// Packs target[i], normals[i] and epsilon into (*out)[i] (sizes must match), with b_z of
/// b = a y + n (n . y), and, when `information` is given, Omega and b's x and y into
/// (*information)[i]. Set-up: allocates; parallel over the points on the threads of `parallel`
/// (null: the calling thread).
void pack_plane_points(const PointCloud& target, const std::vector<Eigen::Vector3d>& normals,
                       double epsilon, const Parallel* parallel, Buffer<PlanePoint>* out,
                       Buffer<PlaneInformation>* information = nullptr);

/// What the plane pass forms the pairs' normals from (pair_normals.hpp): the source normals of
/// the association table's rows, one per row, and the rotation R_target_source at which the table
/// was made (the pairs' normals are frozen there between associations).
struct PairNormalSource {
  const std::vector<Eigen::Vector3d>* normals = nullptr;
  Eigen::Matrix3d R_target_source = Eigen::Matrix3d::Identity();
};

/// A pair's normal n = s / |s| as the plane pass uses it: s and q = 1 / |s|^2 (so that
/// n n^T = q s s^T and (n . e)^2 = q (s . e)^2: one division, no square root); s = 0 and q = 0
/// for a pair without a normal (Omega = I).
struct PairNormal {
  Eigen::Vector3d s;
  double q;
};

/// The plane error model's data (null = point model).
struct PlaneModel {
  // Per target point (pack_plane_points), same order and positions as the target cloud passed
  // to evaluate().
  const Buffer<PlanePoint>* points = nullptr;
  // The same points' Omega and b (pack_plane_points); needed without pair_source, unused with it.
  const Buffer<PlaneInformation>* information = nullptr;
  double epsilon = ExpertOptions{}.plane_epsilon;  // in-plane weight (a of the pair normals;
                                                   // points carry their own a)
  // Optional (pair_normals.hpp): when set, each pair's normal, the mean of its target point's
  // and its source point's, replaces its target point's normal in Omega (fixed for the pass: not
  // a function of T).
  const PairNormalSource* pair_source = nullptr;
};

struct Evaluation {
  double cost = 0.0;               // 1/2 sum w_new |e|^2 (weights computed at this pose)
  double cost_prev_weights = 0.0;  // 1/2 sum w_prev |e|^2 (when w_prev was given, else 0)
  double weight_sum = 0.0;         // sum of w_new
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
};

/// Per-block partial sums of a pass. Point model: S0, S1, S2 (H from 10 numbers, header
/// comment); plane model: the 6x6 H directly (upper triangle used).
struct BlockSums {
  double S0, cost, cost_prev;
  Eigen::Vector3d S1, ebar, ebar_cross_p;
  Eigen::Matrix3d S2;
  Matrix6d H;
};

/// What the pair normals' first pass of an inner solve keeps for the solve's later passes, per
/// table slot (stride k): the table and the rotation the pair normals use are fixed through a
/// solve (PairNormalSource), so every pass forms the same ones. slots: null, or room for the
/// table's slots; fill: the pass forms the pair normals and writes the memo
/// (pair_normals_of_point), else it forms them from the memo (pair_normals_from_memo), the same
/// to the bit. Unused without pair normals.
struct PairNormalMemo {
  double* slots = nullptr;
  bool fill = true;
};

class NormalEquations {
 public:
  static constexpr std::size_t kBlockSize = 256;

  /// Sizes the per-block partial sums and the pair normals' slots for k neighbours (set-up, not
  /// in the loop).
  void resize(std::size_t source_points, int k);

  /// One pass at pose T (maps source into the target's frame): w_new[j*k+m] = E-step weights at
  /// T, and out = costs, H and g under w_new. If w_prev is not null, also the cost at T under
  /// w_prev (the LM step test compares costs under the same weights). w_prev may be w_new (in
  /// place: each point's previous weights are read before its new ones are written, so the
  /// pointers must not be declared __restrict), but must not overlap it otherwise; r_sq must
  /// not overlap either. If r_sq is not null, also the squared errors r_sq[j*k+m] = |e|^2 (the
  /// solver passes null: each point's are kept on the stack). Arrays have the association
  /// table's stride k. A row left out (AssociationTable::left_out) adds nothing: its weights are
  /// 0 and its r_sq slots are not written.
  /// With plane != null the plane error model is used (r_sq then holds e^T Omega e). With pair
  /// normals, memo.slots (if not null) keeps them from a pass to the next (PairNormalMemo).
  void evaluate(const PointCloud& source, const PointCloud& target, const AssociationTable& assoc,
                const WeightParams& weights, const Eigen::Isometry3d& T, const double* w_prev,
                double* w_new, double* r_sq, const Parallel* parallel, Evaluation* out,
                const PlaneModel* plane = nullptr, PairNormalMemo memo = {});

  /// Whether evaluate() may take the pair normals' points four at a time (four_points.hpp) where
  /// the CPU allows: on by default; the same results to the bit either way (tests compare).
  void set_four_points(bool on) { four_points_ = on; }

  /// sum_j J_j^T (sum_k w_kj n_k n_k^T) J_j at T with the given weights (n_k n_k^T replaced by I
  /// for a target point without a normal): the information of the surface-normal part of the
  /// plane model alone (no epsilon), whose null directions are the motions the target's geometry
  /// leaves unconstrained. Once per registration, on the threads of `parallel` (null: the calling
  /// thread): summed per block of kBlockSize source points into *blocks (resized; allocates only
  /// when it grows), then over the blocks in order, so that the sum does not depend on the
  /// thread count.
  static Matrix6d normal_information(const PointCloud& source, const AssociationTable& assoc,
                                     const Eigen::Isometry3d& T, const double* w,
                                     const Buffer<PlanePoint>& target_points,
                                     const Parallel* parallel, std::vector<Matrix6d>* blocks);

 private:
  template <bool kPlane, bool kPairNormals, class Kernel>
  void pass(const Kernel& e_step, const PointCloud& source, const PointCloud& target,
            const AssociationTable& assoc, const Eigen::Isometry3d& T, const double* w_prev,
            double* w_new, double* r_sq, const Parallel* parallel, const PlaneModel* plane,
            PairNormalMemo memo, const DyadicStudentT* four_points);
  std::vector<BlockSums> blocks_;
  bool four_points_ = true;
  // With pair normals, k per block of source points: the pass forms a point's there.
  std::vector<PairNormal> pair_normals_;
};

}  // namespace detail
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
