// guard.hpp - keeps exceptions from crossing the ppcr_io API (private to ppcr_io).
#pragma once

#include <exception>
#include <new>
#include <string>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

/// Runs body() (which returns a Status) and turns any exception it throws (std::bad_alloc when a
/// huge but plausible file does not fit in memory, ...) into kIoError "<name>: <what>".
template <typename Body>
Status guarded(const std::string& name, Body&& body) noexcept {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    try {
      return Status(StatusCode::kIoError, name + ": out of memory");
    } catch (...) {
      return Status(StatusCode::kIoError, std::string());
    }
  } catch (const std::exception& e) {
    try {
      return Status(StatusCode::kIoError, name + ": unexpected error: " + e.what());
    } catch (...) {
      return Status(StatusCode::kIoError, std::string());
    }
  } catch (...) {
    return Status(StatusCode::kIoError, std::string());
  }
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
