// test_data.hpp - where the real scans are (read in place, never copied into the project).
#pragma once

#include <cstdlib>
#include <string>

namespace ppcr_test {

/// $PPCR_DATA_DIR if set, else the folder configured at build time (../shared/data).
inline std::string data_dir() {
  const char* env = std::getenv("PPCR_DATA_DIR");
  if (env != nullptr && env[0] != '\0') return env;
  return PPCR_DATA_DIR;
}

inline std::string data_path(const std::string& relative) { return data_dir() + "/" + relative; }

}  // namespace ppcr_test
