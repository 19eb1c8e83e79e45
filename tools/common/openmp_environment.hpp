// openmp_environment.hpp - the tools' OpenMP threads sleep when idle.
//
// GCC's OpenMP runtime reads OMP_WAIT_POLICY once, when the program loads: by default a thread
// that has finished a parallel loop spins for a while before it sleeps, taking a core another
// busy process could use (several ppcr processes on one machine, a benchmark beside its peers).
// With OMP_WAIT_POLICY=passive it sleeps at once. A tool cannot set it for its own runtime after
// loading, so when the variable is unset it sets it and runs itself again (execv of
// /proc/self/exe, same arguments): a user's own value is kept, and if the new run cannot start,
// the tool goes on as it is. Without OpenMP (PPCR_USE_OPENMP off) this does nothing.
#pragma once

#include <unistd.h>

#include <cstdlib>

namespace ppcr_tools {

inline void use_passive_openmp_threads(char** argv) {
#if defined(PPCR_USE_OPENMP) && defined(__linux__)
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  if (::setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
  ::execv("/proc/self/exe", argv);  // returns only on failure: go on with the default policy
#else
  (void)argv;
#endif
}

}  // namespace ppcr_tools
