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

/// True under CI=true or PPCR_STRICT=1 (tools/test.sh sets it in CI): what would be skipped for
/// want of data or a tool must fail instead.
inline bool strict() {
  const char* ci = std::getenv("CI");
  const char* flag = std::getenv("PPCR_STRICT");
  return (ci != nullptr && std::string(ci) == "true") ||
         (flag != nullptr && std::string(flag) == "1");
}

}  // namespace ppcr_test
