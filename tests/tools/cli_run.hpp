// cli_run.hpp - runs the built ppcr_cli as a user does (std::system), for the CLI tests.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace cli_test {

// One folder per process: ctest runs the test cases in parallel.
inline const std::string kDir = std::string(PPCR_CLI_TEST_DIR) + "/" + std::to_string(getpid());

struct Run {
  int status;
  std::string out, err;
};

inline std::string read_text(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// Runs ppcr_cli with `arguments`; stdout goes to `stdout_to` (a path), stderr is kept.
inline Run run_cli(const std::string& arguments, const std::string& stdout_to = kDir + "/out.txt") {
  std::filesystem::create_directories(kDir);
  const std::string err = kDir + "/err.txt";
  const std::string command = std::string("'") + PPCR_CLI_EXE + "' " + arguments + " > '" +
                              stdout_to + "' 2> '" + err + "'";
  const int status = std::system(command.c_str());
  Run r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, "", read_text(err)};
  if (stdout_to != "/dev/full") r.out = read_text(stdout_to);
  return r;
}

}  // namespace cli_test
