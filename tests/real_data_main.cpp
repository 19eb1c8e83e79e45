// The Catch2 main of the tests that read ../shared/data (PPCR_DATA_DIR at configure time, or
// the environment variable PPCR_DATA_DIR). Without the folder they are skipped: exit code 77,
// which ctest reports as "Skipped", with a message naming the folder looked for.
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
    std::fprintf(stderr,
                 "SKIPPED: real-scan data folder '%s' not found (set PPCR_DATA_DIR or put "
                 "../shared/data beside the checkout)\n",
                 dir.c_str());
    return 77;
  }
  return Catch::Session().run(argc, argv);
}
