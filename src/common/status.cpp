// status.cpp - names of status codes.
#include "ppcr/status.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {

const char* to_string(StatusCode code) {
  switch (code) {
    case StatusCode::kOk:
      return "ok";
    case StatusCode::kInvalidArgument:
      return "invalid_argument";
    case StatusCode::kEmptyCloud:
      return "empty_cloud";
    case StatusCode::kNoCorrespondences:
      return "no_correspondences";
    case StatusCode::kNumericalFailure:
      return "numerical_failure";
    case StatusCode::kIoError:
      return "io_error";
    case StatusCode::kParseError:
      return "parse_error";
  }
  return "unknown";
}

std::string Status::to_string() const {
  if (ok()) return "ok";
  return std::string(ppcr::to_string(code_)) + ": " + message_;
}

}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
