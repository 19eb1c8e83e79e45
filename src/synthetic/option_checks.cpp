// option_checks.cpp - range checks of the sensor and measurement options.
#include "option_checks.hpp"

#include <cmath>
#include <sstream>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {
namespace {

constexpr double kMaxOutlierFraction = 0.95;
constexpr long long kMaxRays = 1LL << 22;  // beams * horizontal_steps (4194304)

}  // namespace

/// Integers as integers (36864000, not 3.6864e+07); other values with 6 significant digits.
std::string number(double value) {
  std::ostringstream text;
  if (std::abs(value) < 1e15 && value == std::floor(value)) {
    text << static_cast<long long>(value);
  } else {
    text << value;
  }
  return text.str();
}

Status invalid(const std::string& name, double value, const std::string& requirement) {
  std::ostringstream message;
  message << name << " = " << number(value) << ": " << requirement;
  return Status(StatusCode::kInvalidArgument, message.str());
}

Status check_sensor(const SensorModel& s, const std::string& prefix) {
  const std::string p = prefix + "sensor.";
  if (s.beams < 1 || s.beams > 1024) return invalid(p + "beams", s.beams, "must be in [1, 1024]");
  if (s.horizontal_steps < 1 || s.horizontal_steps > 36000) {
    return invalid(p + "horizontal_steps", s.horizontal_steps, "must be in [1, 36000]");
  }
  if (static_cast<long long>(s.beams) * s.horizontal_steps > kMaxRays) {
    return invalid(p + "beams * horizontal_steps",
                   static_cast<double>(s.beams) * s.horizontal_steps,
                   "must be at most 4194304 rays per scan");
  }
  if (!(std::abs(s.fov_up_deg) <= 90.0)) {
    return invalid(p + "fov_up_deg", s.fov_up_deg, "must be in [-90, 90] degrees");
  }
  if (!(std::abs(s.fov_down_deg) <= 90.0)) {
    return invalid(p + "fov_down_deg", s.fov_down_deg, "must be in [-90, 90] degrees");
  }
  if (s.beams > 1 && !(s.fov_down_deg < s.fov_up_deg)) {
    return invalid(p + "fov_down_deg", s.fov_down_deg,
                   "must be below fov_up_deg = " + number(s.fov_up_deg));
  }
  if (s.beams == 1 && !(s.fov_down_deg <= s.fov_up_deg)) {
    return invalid(p + "fov_down_deg", s.fov_down_deg,
                   "must not exceed fov_up_deg = " + number(s.fov_up_deg));
  }
  if (!(s.min_range >= 0.0 && std::isfinite(s.min_range))) {
    return invalid(p + "min_range", s.min_range, "must be finite and >= 0 (metres)");
  }
  if (!(s.max_range > s.min_range && s.max_range <= 10000.0)) {
    return invalid(
        p + "max_range", s.max_range,
        "must be above min_range = " + number(s.min_range) + " and at most 10000 (metres)");
  }
  if (s.projection != Projection::kSpinning && s.projection != Projection::kPinhole) {
    return invalid(p + "projection", static_cast<int>(s.projection),
                   "must be Projection::kSpinning or Projection::kPinhole");
  }
  if (s.projection == Projection::kSpinning) {
    if (!(s.horizontal_fov_deg > 0.0 && s.horizontal_fov_deg <= 360.0)) {
      return invalid(p + "horizontal_fov_deg", s.horizontal_fov_deg,
                     "must be in (0, 360] degrees for a spinning sensor");
    }
    return Status::Ok();
  }
  if (!(s.horizontal_fov_deg > 0.0 && s.horizontal_fov_deg < 180.0)) {
    return invalid(p + "horizontal_fov_deg", s.horizontal_fov_deg,
                   "must be in (0, 180) degrees for a depth camera (Projection::kPinhole)");
  }
  if (!(std::abs(s.fov_up_deg) < 90.0)) {
    return invalid(p + "fov_up_deg", s.fov_up_deg,
                   "must be in (-90, 90) degrees for a depth camera (Projection::kPinhole)");
  }
  if (!(std::abs(s.fov_down_deg) < 90.0)) {
    return invalid(p + "fov_down_deg", s.fov_down_deg,
                   "must be in (-90, 90) degrees for a depth camera (Projection::kPinhole)");
  }
  return Status::Ok();
}

Status check_measurement(const Measurement& m, const std::string& prefix) {
  if (!(m.noise_sigma >= 0.0 && std::isfinite(m.noise_sigma))) {
    return invalid(prefix + "noise_sigma", m.noise_sigma, "must be finite and >= 0 (metres)");
  }
  if (!(m.noise_per_metre >= 0.0 && m.noise_per_metre <= 1.0)) {
    return invalid(prefix + "noise_per_metre", m.noise_per_metre, "must be in [0, 1]");
  }
  if (!(m.depth_quantisation >= 0.0 && m.depth_quantisation <= 1000.0)) {
    return invalid(prefix + "depth_quantisation", m.depth_quantisation,
                   "must be in [0, 1000] (1/metres)");
  }
  if (!(m.outlier_fraction >= 0.0 && m.outlier_fraction <= kMaxOutlierFraction)) {
    return invalid(prefix + "outlier_fraction", m.outlier_fraction, "must be in [0, 0.95]");
  }
  return Status::Ok();
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
