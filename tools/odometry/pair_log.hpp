// pair_log.hpp - the per-pair quality CSV of a sequence, one complete line per registered scan:
//   scan,file,method,fitness,quality,quality_reason,inlier_rmse,iterations,stop_reason,time_ms
// (fitness, quality and inlier_rmse are ppcr's measures: empty for a peer; time_ms is the
// wall time of set_target + align, the peers' whole run).
#pragma once

#include <string>

#include "odometry/line_file.hpp"
#include "odometry/pair_registrar.hpp"
#include "ppcr/status.hpp"

namespace ppcr_odometry {

class PairLog {
 public:
  /// Creates the file and writes the header.
  ppcr::Status open(const std::string& path);
  /// Appends a row; nothing when the file was not opened.
  ppcr::Status append(std::size_t scan, const std::string& file, const std::string& method,
                      const PairOutcome& outcome, double time_ms);
  ppcr::Status close() { return file_.close(); }

 private:
  LineFile file_;
};

}  // namespace ppcr_odometry
