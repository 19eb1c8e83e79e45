// line_file.cpp - whole lines, written unbuffered.
#include "odometry/line_file.hpp"

#include <cerrno>
#include <cstring>

namespace ppcr_odometry {
namespace {

ppcr::Status io_error(const std::string& path, const std::string& what) {
  return ppcr::Status(ppcr::StatusCode::kIoError,
                      path + ": cannot " + what + ": " + std::strerror(errno));
}

}  // namespace

LineFile::~LineFile() {
  if (file_ != nullptr) std::fclose(file_);
}

ppcr::Status LineFile::open(const std::string& path) {
  if (file_ != nullptr) std::fclose(file_);
  path_ = path;
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) return io_error(path, "write");
  // Unbuffered: every fwrite below is one write() of a whole line; nothing waits in a buffer.
  std::setvbuf(file_, nullptr, _IONBF, 0);
  return ppcr::Status::Ok();
}

ppcr::Status LineFile::write_line(const std::string& line) {
  if (file_ == nullptr) {
    return ppcr::Status(ppcr::StatusCode::kIoError, path_ + ": write to a closed file");
  }
  const std::string whole = line + '\n';
  if (std::fwrite(whole.data(), 1, whole.size(), file_) != whole.size()) {
    return io_error(path_, "write");
  }
  return ppcr::Status::Ok();
}

ppcr::Status LineFile::close() {
  if (file_ == nullptr) return ppcr::Status::Ok();
  const int closed = std::fclose(file_);
  file_ = nullptr;
  return closed == 0 ? ppcr::Status::Ok() : io_error(path_, "close");
}

}  // namespace ppcr_odometry
