// transform_io.cpp - reading and writing a rigid transform as a 4x4 matrix in text
// (see read_transform / write_transform in ppcr/io.hpp).
#include <charconv>
#include <cmath>
#include <string>

#include "file_access.hpp"
#include "guard.hpp"
#include "ppcr/io.hpp"
#include "ppcr/se3.hpp"
#include "text_scan.hpp"
#include "writer_common.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace {

// Same tolerance as the core's default for se3::is_rigid: R^T R = I and det R = 1.
constexpr double kRotationTolerance = 1e-6;
// The last row must be (0 0 0 1) much more tightly: it is not the result of any computation.
constexpr double kLastRowTolerance = 1e-9;
// A transform file is a few hundred bytes; anything far larger is not one.
constexpr std::size_t kMaxTransformFileBytes = 1 << 20;
constexpr detail::ReadLimits kTransformLimits{kMaxTransformFileBytes, kMaxTransformFileBytes,
                                              "a 4x4 matrix"};

std::string number_text(double v) {
  char buffer[detail::kMaxDoubleChars];
  return std::string(buffer, detail::format_double(v, buffer));
}

// A short rendering (6 significant digits) for deviations and tolerances in messages.
std::string short_number(double v) {
  char buffer[detail::kMaxDoubleChars];
  const std::to_chars_result r =
      std::to_chars(buffer, buffer + sizeof(buffer), v, std::chars_format::general, 6);
  return std::string(buffer, static_cast<std::size_t>(r.ptr - buffer));
}

// Why M is not a rigid transform, or "" if it is.
std::string rigidity_problem(const Eigen::Matrix4d& M) {
  const Eigen::RowVector4d last_row = M.row(3);
  const double last_row_deviation =
      (last_row - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff();
  if (!(last_row_deviation <= kLastRowTolerance)) {
    return "the last row is (" + number_text(M(3, 0)) + " " + number_text(M(3, 1)) + " " +
           number_text(M(3, 2)) + " " + number_text(M(3, 3)) + "), expected (0 0 0 1)";
  }
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  const double orthonormality_deviation =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(orthonormality_deviation <= kRotationTolerance)) {
    return "the rotation part is not orthonormal: R^T R deviates from I by " +
           short_number(orthonormality_deviation) + " (tolerance " +
           short_number(kRotationTolerance) + ")";
  }
  const double det = R.determinant();
  if (!(std::abs(det - 1.0) <= kRotationTolerance)) {
    return "det R = " + short_number(det) +
           (det < 0 ? " (a reflection), expected +1" : ", expected +1");
  }
  if (!se3::is_rigid(M, kRotationTolerance)) return "se3::is_rigid rejects it";
  return std::string();
}

Status parse_transform(const std::string& name, const char* data, std::size_t size,
                       Eigen::Isometry3d* T) {
  if (size == 0) return Status(StatusCode::kParseError, name + ": file is empty (0 bytes)");
  if (size > kMaxTransformFileBytes) {
    return Status(StatusCode::kParseError, name + ": " + std::to_string(size) +
                                               " bytes is far too large for a 4x4 matrix (limit " +
                                               std::to_string(kMaxTransformFileBytes) + ")");
  }
  double values[16];
  std::size_t count = 0;
  detail::LineCursor cursor(data, size, detail::utf8_bom_size(data, size));
  std::string_view line;
  while (cursor.next(&line)) {
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    detail::Tokenizer tokens(line);
    std::string_view token;
    while (tokens.next(&token)) {
      const std::string where = name + ": line " + std::to_string(cursor.line_number()) +
                                ", column " + std::to_string(tokens.column()) + ": ";
      if (count == 16) {
        return Status(StatusCode::kParseError,
                      where + "a 17th value " + "'" + detail::escape_for_message(token) +
                          "' (expected 16 numbers: a 4x4 matrix, or 12: its top 3 rows)");
      }
      double v = 0.0;
      if (!detail::parse_double(token, &v)) {
        return Status(StatusCode::kParseError,
                      where + "expected a number, saw '" + detail::escape_for_message(token) + "'");
      }
      if (!std::isfinite(v)) {
        return Status(StatusCode::kParseError,
                      where + "non-finite value '" + detail::escape_for_message(token) + "'");
      }
      values[count++] = v;
    }
  }
  if (count != 12 && count != 16) {
    return Status(StatusCode::kParseError,
                  name + ": found " + std::to_string(count) +
                      " numbers, expected 16 (a 4x4 matrix, row by row) or 12 (its top 3 rows)");
  }
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  for (std::size_t i = 0; i < count; ++i) {
    M(static_cast<Eigen::Index>(i / 4), static_cast<Eigen::Index>(i % 4)) = values[i];
  }
  const std::string problem = rigidity_problem(M);
  if (!problem.empty()) {
    return Status(StatusCode::kParseError, name + ": not a rigid transform: " + problem);
  }
  M.row(3) << 0.0, 0.0, 0.0, 1.0;
  T->matrix() = M;
  return Status::Ok();
}

}  // namespace

Status read_transform_from_buffer(const std::string& name, const char* data, std::size_t size,
                                  Eigen::Isometry3d* T) {
  return detail::guarded(name, [&]() -> Status {
    if (T == nullptr) {
      return Status(StatusCode::kInvalidArgument, name + ": null output transform");
    }
    if (data == nullptr && size > 0) {
      return Status(StatusCode::kInvalidArgument, name + ": null data pointer");
    }
    return parse_transform(name, data, size, T);
  });
}

Status read_transform(const std::string& path, Eigen::Isometry3d* T) {
  return detail::guarded(path, [&]() -> Status {
    if (T == nullptr) {
      return Status(StatusCode::kInvalidArgument, path + ": null output transform");
    }
    std::string bytes;
    Status status = detail::read_file_bytes(path, kTransformLimits, &bytes);
    if (!status.ok()) return status;
    return parse_transform(path, bytes.data(), bytes.size(), T);
  });
}

Status write_transform(const std::string& path, const Eigen::Isometry3d& T) {
  return detail::guarded(path, [&]() -> Status {
    const Eigen::Matrix4d& M = T.matrix();
    if (!M.allFinite()) {
      return Status(StatusCode::kInvalidArgument,
                    path + ": not written: the transform has a non-finite entry");
    }
    const std::string problem = rigidity_problem(M);
    if (!problem.empty()) {
      return Status(StatusCode::kInvalidArgument,
                    path + ": not written: not a rigid transform: " + problem);
    }
    std::string text;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) {
        text += number_text(M(r, c));
        text += c < 3 ? ' ' : '\n';
      }
    }
    detail::FileWriter out;
    Status status = out.open(path);
    if (!status.ok()) return status;
    out.append(text);
    return out.finish();
  });
}

}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
