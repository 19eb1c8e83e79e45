// option_checks.hpp - the checks shared by make_scan_pair() and make_scan_sequence(): the sensor
// and the measurement model (internal to ppcr_synthetic). Messages name the field with the
// caller's prefix ("ScanOptions.", "SequenceOptions.") and the value seen.
#pragma once

#include <string>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"
#include "ppcr/synthetic.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace synthetic {
namespace internal {

/// Integers as integers (36864000, not 3.6864e+07); other values with 6 significant digits.
std::string number(double value);

/// kInvalidArgument "<name> = <value>: <requirement>".
Status invalid(const std::string& name, double value, const std::string& requirement);

/// The sensor's fields (see SensorModel), named prefix + "sensor.<field>".
Status check_sensor(const SensorModel& sensor, const std::string& prefix);

/// The measurement model shared by the pair and the sequence: noise_sigma, noise_per_metre,
/// depth_quantisation and outlier_fraction, named prefix + field.
struct Measurement {
  double noise_sigma = 0.0;
  double noise_per_metre = 0.0;
  double depth_quantisation = 0.0;
  double outlier_fraction = 0.0;
};
Status check_measurement(const Measurement& measurement, const std::string& prefix);

/// check_sensor, then check_measurement, of ScanOptions or SequenceOptions (their fields of the
/// same names).
template <class Options>
Status check_sensor_and_measurement(const Options& o, const std::string& prefix) {
  const Status status = check_sensor(o.sensor, prefix);
  if (!status.ok()) return status;
  Measurement measurement;
  measurement.noise_sigma = o.noise_sigma;
  measurement.noise_per_metre = o.noise_per_metre;
  measurement.depth_quantisation = o.depth_quantisation;
  measurement.outlier_fraction = o.outlier_fraction;
  return check_measurement(measurement, prefix);
}

}  // namespace internal
}  // namespace synthetic
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
