// progress.cpp - a progress line a second.
#include "odometry/progress.hpp"

#include <cstdio>

namespace ppcr_odometry {

Progress::Progress(std::size_t total, bool quiet)
    : total_(total), quiet_(quiet), start_(Clock::now()), last_(start_) {}

double Progress::seconds() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

double Progress::rate(std::size_t done) const {
  const double elapsed = seconds();
  return elapsed > 0.0 ? static_cast<double>(done) / elapsed : 0.0;
}

void Progress::update(std::size_t done) {
  const Clock::time_point now = Clock::now();
  if (quiet_ || (now - last_ < std::chrono::seconds(1) && done < total_)) return;
  last_ = now;
  const double r = rate(done);
  const double left = r > 0.0 ? static_cast<double>(total_ - done) / r : 0.0;
  std::fprintf(stderr, "ppcr_odometry: scan %zu of %zu, %.2f scans/s, %.0f s left\n", done, total_,
               r, left);
}

}  // namespace ppcr_odometry
