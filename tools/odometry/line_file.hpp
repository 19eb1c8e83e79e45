// line_file.hpp - a text file written one complete line at a time: each line goes out in one
// write and is flushed at once, so that after any stop (an error, a kill, a crash) the file holds
// whole lines only, one per record written before the stop.
#pragma once

#include <cstdio>
#include <string>

#include "ppcr/status.hpp"

namespace ppcr_odometry {

class LineFile {
 public:
  LineFile() = default;
  ~LineFile();
  LineFile(const LineFile&) = delete;
  LineFile& operator=(const LineFile&) = delete;

  /// Creates (or truncates) the file; the message names the path and the system's reason.
  ppcr::Status open(const std::string& path);
  /// Writes `line` (without its '\n', which is added) in one write and flushes it.
  ppcr::Status write_line(const std::string& line);
  /// Closes the file, reporting a failed close (a full disk can show only then).
  ppcr::Status close();
  bool is_open() const { return file_ != nullptr; }
  const std::string& path() const { return path_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
};

}  // namespace ppcr_odometry
