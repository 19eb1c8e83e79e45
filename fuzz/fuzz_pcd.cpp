// fuzz_pcd.cpp - libFuzzer target: the PCD reader on arbitrary bytes (from memory, no disk).
#include <cstddef>
#include <cstdint>

#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ppcr_fuzz::check_read("fuzz.pcd", ppcr::io::Format::kPcd, data, size);
  return 0;
}
