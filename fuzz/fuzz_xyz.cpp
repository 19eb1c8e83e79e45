// fuzz_xyz.cpp - libFuzzer target: the XYZ/CSV/PTS reader on arbitrary bytes (from memory, no
// disk), then the same bytes through format detection (a name without extension, Format::kAuto).
#include <cstddef>
#include <cstdint>

#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ppcr_fuzz::check_read("fuzz.xyz", ppcr::io::Format::kXyz, data, size);
  ppcr_fuzz::check_read("fuzz_auto", ppcr::io::Format::kAuto, data, size);
  return 0;
}
