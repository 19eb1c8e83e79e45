// writer_common.hpp - what the format writers share (private to ppcr_io).
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

/// Writers refuse clouds with a non-finite coordinate (readers would drop those points, so the
/// round trip would not be exact): kInvalidArgument naming the path and the first such point.
inline Status check_finite_cloud(const std::string& path, const PointCloud& cloud) {
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud[i].allFinite()) {
      return Status(
          StatusCode::kInvalidArgument,
          path + ": not written: point " + std::to_string(i) + " has a non-finite coordinate");
    }
  }
  return Status::Ok();
}

/// Largest text of format_double (sign, 17 digits, point, exponent), with room to spare.
constexpr std::size_t kMaxDoubleChars = 32;

/// Writes value as "%.17g" would (17 significant digits, which reads back bit-identically), but
/// locale-independently. Returns the number of characters written to out (no NUL).
inline std::size_t format_double(double value, char* out) {
  const std::to_chars_result r =
      std::to_chars(out, out + kMaxDoubleChars, value, std::chars_format::general, 17);
  return static_cast<std::size_t>(r.ptr - out);
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
