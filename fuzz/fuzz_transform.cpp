// fuzz_transform.cpp - libFuzzer target: the transform-file parser on arbitrary bytes.
// Invariant: an accepted matrix is finite with last row exactly (0 0 0 1); a refusal has a
// message naming the file.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "ppcr/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const ppcr::Status status = ppcr::io::read_transform_from_buffer(
      "fuzz_T.txt", reinterpret_cast<const char*>(data), size, &T);
  if (status.ok()) {
    if (!T.matrix().allFinite()) std::abort();
    if (T.matrix().row(3) != Eigen::RowVector4d(0, 0, 0, 1)) std::abort();
  } else if (status.message().find("fuzz_T.txt") == std::string::npos) {
    std::abort();
  }
  return 0;
}
