// status.hpp - the one error channel of the ppcr core.
//
// No function of the core throws across its API or prints: each returns a Status (or a result
// struct holding one). A Status is a code plus a human-readable message that names the parameter
// or input at fault and the value seen.
#pragma once

#include <string>
#include <utility>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

enum class StatusCode {
  kOk = 0,
  kInvalidArgument,    // a parameter out of range (radius <= 0, max_neighbours < 1, dof <= 0, ...)
  kEmptyCloud,         // a cloud with no (finite) point, or too few points after filtering
  kNoCorrespondences,  // no source point has a target point within the radius
  kNumericalFailure,   // the 6x6 solve failed or produced non-finite values
  kIoError,            // ppcr_io only: a file could not be opened, read or written
  kParseError,         // ppcr_io only: a file is malformed (the message names file and position)
};

/// Short stable name of a code ("ok", "invalid_argument", ...), for logs and JSON.
const char* to_string(StatusCode code);

class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status Ok() { return Status(); }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

  /// "<code>: <message>" or "ok".
  std::string to_string() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
