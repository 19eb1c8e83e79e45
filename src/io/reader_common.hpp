// reader_common.hpp - what every format reader shares (private to ppcr_io): the input buffer it
// reads, the sink that keeps finite points and counts the others, and error construction.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "ppcr/abi.hpp"
#include "ppcr/io.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

/// The bytes of one file (or fuzzer buffer) and the name to use in messages. The data need not
/// be NUL-terminated; readers never look past data + size.
struct Input {
  const std::string& name;
  const char* data;
  std::size_t size;

  const unsigned char* bytes() const { return reinterpret_cast<const unsigned char*>(data); }
};

/// kParseError "<name>: <what>".
inline Status parse_error(const Input& in, const std::string& what) {
  return Status(StatusCode::kParseError, in.name + ": " + what);
}

/// Collects points into a cloud, dropping (and counting) points with a non-finite coordinate.
class PointSink {
 public:
  explicit PointSink(PointCloud* cloud) : cloud_(cloud) {}
  void add(double x, double y, double z) {
    if (std::isfinite(x) && std::isfinite(y) && std::isfinite(z)) {
      cloud_->emplace_back(x, y, z);
    } else {
      ++non_finite_;
    }
  }
  std::size_t non_finite() const { return non_finite_; }

 private:
  PointCloud* cloud_;
  std::size_t non_finite_ = 0;
};

/// Fills the report's counts and turns "no finite point" into kEmptyCloud.
inline Status finish_read(const Input& in, std::size_t points_in_file, const PointSink& sink,
                          const PointCloud& cloud, ReadReport* report) {
  report->points_in_file = points_in_file;
  report->non_finite_dropped = sink.non_finite();
  if (cloud.empty()) {
    if (points_in_file == 0) {
      return Status(StatusCode::kEmptyCloud, in.name + ": the file holds zero points");
    }
    return Status(StatusCode::kEmptyCloud,
                  in.name + ": none of the " + std::to_string(points_in_file) +
                      " points in the file is finite (all have a NaN or infinite coordinate)");
  }
  return Status::Ok();
}

/// a * b, or false if the product does not fit in 64 bits.
inline bool checked_mul(std::uint64_t a, std::uint64_t b, std::uint64_t* product) {
  if (a != 0 && b > UINT64_MAX / a) return false;
  *product = a * b;
  return true;
}

/// a + b, or false if the sum does not fit in 64 bits.
inline bool checked_add(std::uint64_t a, std::uint64_t b, std::uint64_t* sum) {
  if (b > UINT64_MAX - a) return false;
  *sum = a + b;
  return true;
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
