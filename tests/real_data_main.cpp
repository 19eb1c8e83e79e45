// The Catch2 main of the tests that read ../shared/data (PPCR_DATA_DIR at configure time, or
// the environment variable PPCR_DATA_DIR). Without the folder they are skipped: the message starts
// with the skip marker (ctest's SKIP_REGULAR_EXPRESSION, tests/CMakeLists.txt) and names the
// folder looked for; the exit code is 77 for other runners. Under CI=true or PPCR_STRICT=1 a
// missing folder is a failure (exit 1): the ground-truth checks on real scans must run there.
#define CATCH_CONFIG_RUNNER
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>
#include <string>

#include "test_data.hpp"

int main(int argc, char* argv[]) {
  bool listing = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--list", 6) == 0) listing = true;
  }
  const std::string dir = ppcr_test::data_dir();
  struct stat st;
  if (!listing && (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))) {
    if (ppcr_test::strict()) {
      std::fprintf(stderr,
                   "FAILED: real-scan data folder '%s' not found, and CI=true or PPCR_STRICT=1 "
                   "requires it (set PPCR_DATA_DIR or put ../shared/data beside the checkout)\n",
                   dir.c_str());
      return 1;
    }
    std::fprintf(stderr,
                 PPCR_TEST_SKIP_MARKER
                 " real-scan data folder '%s' not found (set PPCR_DATA_DIR or put "
                 "../shared/data beside the checkout)\n",
                 dir.c_str());
    return 77;
  }
  return Catch::Session().run(argc, argv);
}
