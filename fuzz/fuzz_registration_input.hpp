// fuzz_registration_input.hpp - how fuzz_registration reads its bytes: a parameter block, then
// two small clouds. Shared by the fuzz target, the seed-corpus writer and the regression tests in
// tests/reliability/ (which replay saved inputs through this same decoder).
//
// Every byte sequence decodes (missing bytes read as 0), and all-zero parameter bytes give the
// library defaults (RegistrationOptions()) with the caps set to 12. Layout, in order (u8 = one
// byte, pos = two bytes, see positive()):
//   flags0 u8   bit0 plane model, bit1 Gaussian, bits2-3 scale mode (0, 3 EM; 1 raw; 2 fixed),
//               bit4 two threads, bit5 no history, bit6 target = source moved by T_gt (+ extra
//               target points), bit7 on_iteration cancels after the 2nd iteration
//   flags1 u8   bit0 explicit EM coarse scale, bit1 cost_drop_max_motion, bit2 flips
//               reject_boundary, bit3 em_min_scale, bit4 source voxel, bit5 target voxel,
//               bit6 flips source_normals, bit7 flips the noise floor (off, or the em_min_scale
//               value when the default is off)
//   criteria u8 (low 4 bits XOR kCriterionCostDrop), max_iterations u8, fixed_iterations u8,
//   lm.max_iterations u8 (each 1..12, 0 -> 12), max_neighbours u8 (1..16, 0 -> the default;
//   240..255
//   -> 32 .. 1024), radius pos, dof pos (times the default), scale pos, plane.epsilon u8,
//   normal_neighbours u8, cost_drop_patience u8, mse_patience u8, successful_steps_patience u8,
//   successful_steps_threshold u8, em_coarse_patience u8, em_min_shrink u8, cost_drop_threshold
//   pos (times 0.01), cost_drop_max_motion pos, em_coarse_max_motion pos, em_min_scale pos,
//   source_voxel pos, target_voxel pos, source unit i8, source offset u8, source count u8
//   (0 .. 64), target unit i8, target offset u8, target count u8, T_initial 6 x i8 (rotation
//   vector in pi/64, translation in target units / 8), T_gt 6 x i8 (pi/256, units / 64),
//   then source points and target points, 3 x i16 (little endian) each.
// A coordinate is i16 / 1024 * unit + offset, unit = 2^(i8 / 3) (2^-42 .. 2^42), offset from a
// table (0 .. 1e300, DBL_MAX), except the reserved codes -32768 .. -32761: NaN, +Inf, -Inf,
// 1e300, -1e300, DBL_MAX, -DBL_MAX, the smallest denormal.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "ppcr/registration.hpp"

namespace ppcr_fuzz {

struct RegistrationInput {
  ppcr::RegistrationOptions options;
  ppcr::PointCloud source, target;
  Eigen::Isometry3d T_initial = Eigen::Isometry3d::Identity();
};

constexpr int kMaxPoints = 64;
constexpr int kMaxIterationsCap = 12;

/// Byte offsets of the parameter block (for writing seeds; the decoder reads in this order).
enum HeaderByte : int {
  kFlags0 = 0,
  kFlags1 = 1,
  kCriteria = 2,
  kMaxIterations = 3,
  kFixedIterations = 4,
  kLmMaxIterations = 5,
  kMaxNeighbours = 6,
  kRadius = 7,  // 2 bytes: exponent (i8), mantissa
  kDof = 9,
  kScale = 11,
  kEpsilon = 13,
  kNormalNeighbours = 14,
  kCostDropPatience = 15,
  kMsePatience = 16,
  kStepsPatience = 17,
  kStepsThreshold = 18,
  kEmCoarsePatience = 19,
  kEmMinShrink = 20,
  kCostDropThreshold = 21,
  kCostDropMaxMotion = 23,
  kEmCoarseMaxMotion = 25,
  kEmMinScale = 27,
  kSourceVoxel = 29,
  kTargetVoxel = 31,
  kSourceCode = 33,  // unit (i8), offset (u8), count (u8)
  kTargetCode = 36,
  kInitialPose = 39,  // 6 x i8
  kTruePose = 45,     // 6 x i8
  kHeaderSize = 51,   // then the points
};

class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t u8() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::int8_t i8() { return static_cast<std::int8_t>(u8()); }
  std::int16_t i16() {
    const unsigned lo = u8(), hi = u8();
    return static_cast<std::int16_t>(static_cast<std::uint16_t>(lo | (hi << 8)));
  }
  /// (1 + m / 256) * 2^e for the exponent byte e as i8 in [-127, 127] (both bytes 0: 1). e = -128
  /// picks a special value by m: 1e-300, 1e300, DBL_MAX, the smallest denormal, 0, -1, NaN, Inf.
  double positive() {
    const int e = i8();
    const int m = u8();
    if (e == -128) {
      constexpr double kSpecial[8] = {1e-300,
                                      1e300,
                                      std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::denorm_min(),
                                      0.0,
                                      -1.0,
                                      std::numeric_limits<double>::quiet_NaN(),
                                      std::numeric_limits<double>::infinity()};
      return kSpecial[m % 8];
    }
    return std::ldexp(1.0 + m / 256.0, e);
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

inline int small_count(std::uint8_t b) {  // 1 .. 12, 0 -> 12
  return 1 + (b + kMaxIterationsCap - 1) % kMaxIterationsCap;
}

inline Eigen::Isometry3d pose_from(ByteReader& in, double angle_unit, double length_unit) {
  Eigen::Vector3d w, t;
  for (int i = 0; i < 3; ++i) w[i] = in.i8() * angle_unit;
  for (int i = 0; i < 3; ++i) t[i] = in.i8() * length_unit;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const double a = w.norm();
  if (a > 0.0) T.linear() = Eigen::AngleAxisd(a, w / a).toRotationMatrix();
  T.translation() = t;
  return T;
}

struct CloudCode {
  double unit = 1.0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  int count = 0;
};

inline CloudCode cloud_code(ByteReader& in) {
  constexpr double kOffsets[16] = {0.0,  1e6,   -1e6,  1e3,   1e9,    1e12,    1e15, 1e17,
                                   1e20, 1e100, 1e150, 1e300, -1e300, 1.7e308, 0.0,  4e-320};
  CloudCode c;
  c.unit = std::ldexp(1.0, in.i8() / 3);
  const double o = kOffsets[in.u8() % 16];
  c.offset = Eigen::Vector3d(o, -0.5 * o, 0.25 * o);
  c.count = in.u8() % (kMaxPoints + 1);
  return c;
}

inline double coordinate(ByteReader& in, const CloudCode& c, int axis) {
  const int v = in.i16();
  switch (v) {
    case -32768:
      return std::numeric_limits<double>::quiet_NaN();
    case -32767:
      return std::numeric_limits<double>::infinity();
    case -32766:
      return -std::numeric_limits<double>::infinity();
    case -32765:
      return 1e300;
    case -32764:
      return -1e300;
    case -32763:
      return std::numeric_limits<double>::max();
    case -32762:
      return -std::numeric_limits<double>::max();
    case -32761:
      return std::numeric_limits<double>::denorm_min();
    default:
      return v / 1024.0 * c.unit + c.offset[axis];
  }
}

inline void read_points(ByteReader& in, const CloudCode& c, ppcr::PointCloud* out) {
  for (int i = 0; i < c.count; ++i) {
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = coordinate(in, c, a);
    out->push_back(p);
  }
}

inline RegistrationInput decode_registration_input(const std::uint8_t* data, std::size_t size) {
  ByteReader in(data, size);
  RegistrationInput r;
  ppcr::RegistrationOptions& o = r.options;
  const std::uint8_t f0 = in.u8(), f1 = in.u8();
  o.error_model = (f0 & 1) ? ppcr::ErrorModel::kPlane : ppcr::ErrorModel::kPoint;
  o.expert.weight_model = (f0 & 2) ? ppcr::WeightModel::kGaussian : ppcr::WeightModel::kStudentT;
  switch ((f0 >> 2) & 3) {
    case 1:
      o.expert.scale_mode = ppcr::ScaleMode::kRaw;
      break;
    case 2:
      o.expert.scale_mode = ppcr::ScaleMode::kFixed;
      break;
    default:
      o.expert.scale_mode = ppcr::ScaleMode::kEM;
  }
  o.num_threads = (f0 & 16) ? 2 : 1;
  o.record_history = (f0 & 32) == 0;
  const bool derived_target = (f0 & 64) != 0;
  if (f0 & 128) {
    o.on_iteration = [](const ppcr::IterationRecord& rec) { return rec.iteration < 2; };
  }

  o.criteria = (in.u8() & 0xFu) ^ ppcr::kCriterionCostDrop;
  o.max_iterations = small_count(in.u8());
  o.expert.fixed_iterations = small_count(in.u8());
  o.expert.lm_max_iterations = small_count(in.u8());
  const std::uint8_t kb = in.u8();
  const ppcr::RegistrationOptions defaults;
  o.max_neighbours =
      kb < 240 ? 1 + (kb + defaults.max_neighbours - 1) % 16 : 32 << ((kb - 240) % 6);  // 32..1024
  o.radius = in.positive();
  o.dof = defaults.dof * in.positive();
  const double scale = in.positive();
  if (o.expert.scale_mode == ppcr::ScaleMode::kFixed || (f1 & 1)) o.expert.scale = scale;
  o.expert.plane_epsilon = ((in.u8() + 12) % 256 + 1) / 256.0;
  o.expert.normal_neighbours = 5 + (in.u8() + 15) % 60;
  o.expert.source_normals = ((f1 & 64) != 0) != defaults.expert.source_normals;   // 0: default
  o.expert.reject_boundary = ((f1 & 4) != 0) != defaults.expert.reject_boundary;  // 0: default
  o.expert.cost_drop_patience = (in.u8() + defaults.expert.cost_drop_patience) % 16;
  o.expert.mse_patience = (in.u8() + 3) % 8;
  o.expert.successful_steps_patience = (in.u8() + 3) % 8;
  o.expert.successful_steps_threshold = (in.u8() + 1) % 8;
  o.expert.em_coarse_patience = (in.u8() + defaults.expert.em_coarse_patience) % 16;
  o.expert.em_min_shrink = ((in.u8() + 63) % 256 + 1) / 256.0;  // 0 -> 0.25, the default
  o.expert.cost_drop_threshold = 0.01 * in.positive();
  const double cd_motion = in.positive(), em_motion = in.positive(), em_min = in.positive();
  const double src_voxel = in.positive(), tgt_voxel = in.positive();
  if (f1 & 2) o.expert.cost_drop_max_motion = cd_motion;
  (void)em_motion;  // (a byte kept so that the corpus keeps its layout)
  if (f1 & 8) o.expert.em_min_scale = em_min;
  if (f1 & 128) o.expert.noise_floor = defaults.expert.noise_floor > 0.0 ? 0.0 : em_min;
  if (f1 & 16) o.source_voxel = src_voxel;
  if (f1 & 32) o.target_voxel = tgt_voxel;

  const double kPi = 3.14159265358979323846;
  const CloudCode sc = cloud_code(in);
  const CloudCode tc = cloud_code(in);
  r.T_initial = pose_from(in, kPi / 64.0, tc.unit / 8.0);
  const Eigen::Isometry3d T_gt = pose_from(in, kPi / 256.0, tc.unit / 64.0);
  read_points(in, sc, &r.source);
  if (derived_target) {
    for (const Eigen::Vector3d& p : r.source) r.target.push_back(T_gt * p);
  }
  read_points(in, tc, &r.target);
  return r;
}

}  // namespace ppcr_fuzz
