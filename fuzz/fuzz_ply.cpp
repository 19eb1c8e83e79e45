// fuzz_ply.cpp - libFuzzer target: the PLY reader on arbitrary bytes (from memory, no disk).
#include <cstddef>
#include <cstdint>

#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ppcr_fuzz::check_read("fuzz.ply", ppcr::io::Format::kPly, data, size);
  return 0;
}
