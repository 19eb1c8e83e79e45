// fuzz_check.hpp - the invariants every ppcr_io reader must keep on ANY input, checked by the
// libFuzzer targets: no crash/UB/leak (the sanitizers see those), and
//  - success: every returned point is finite, and returned + dropped = points in the file;
//  - failure: the cloud is empty and the message is not (and names the file).
// A violated invariant aborts, which libFuzzer reports as a crash with the input saved.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "ppcr/io.hpp"

namespace ppcr_fuzz {

inline void check_read(const char* name, ppcr::io::Format format, const std::uint8_t* data,
                       std::size_t size) {
  ppcr::PointCloud cloud;
  ppcr::io::ReadReport report;
  const ppcr::Status status = ppcr::io::read_cloud_from_buffer(
      name, reinterpret_cast<const char*>(data), size, format, &cloud, &report);
  if (status.ok()) {
    for (const Eigen::Vector3d& p : cloud) {
      if (!p.allFinite()) std::abort();
    }
    if (cloud.empty()) std::abort();
    if (cloud.size() + report.non_finite_dropped != report.points_in_file) std::abort();
  } else {
    if (!cloud.empty()) std::abort();
    if (status.message().find(name) == std::string::npos) std::abort();
  }
}

}  // namespace ppcr_fuzz
