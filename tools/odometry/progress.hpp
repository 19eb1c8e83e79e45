// progress.hpp - the progress of a sequence on stderr: "scan i of N, r scans/s, s left", at
// most once a second, and the final rate.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace ppcr_odometry {

class Progress {
 public:
  Progress(std::size_t total, bool quiet);
  /// Scan `done` (1-based count of scans registered) is finished.
  void update(std::size_t done);
  /// Scans registered per second since the start.
  double rate(std::size_t done) const;
  double seconds() const;

 private:
  using Clock = std::chrono::steady_clock;
  std::size_t total_;
  bool quiet_;
  Clock::time_point start_, last_;
};

}  // namespace ppcr_odometry
