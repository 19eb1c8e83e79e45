// file_access.cpp - whole-file reads and checked buffered writes (see file_access.hpp).
#include "file_access.hpp"

#include <cerrno>
#include <filesystem>
#include <system_error>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

std::string reason(int error_number) {
  if (error_number == 0) return "unknown error";
  return std::error_code(error_number, std::generic_category()).message();
}

constexpr std::size_t kWriteChunkBytes = 1 << 20;

// Removes a partly written file, but only a regular file: never a device such as /dev/full.
void remove_partial(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) std::filesystem::remove(path, ec);
}
constexpr std::size_t kReadChunkBytes = 1 << 16;

}  // namespace

Status read_file_bytes(const std::string& path, std::string* bytes) {
  bytes->clear();
  if (path.empty()) return Status(StatusCode::kIoError, "empty file name");
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (st.type() == std::filesystem::file_type::not_found) {
    return Status(StatusCode::kIoError, path + ": cannot open: no such file");
  }
  if (st.type() == std::filesystem::file_type::directory) {
    return Status(StatusCode::kIoError, path + ": cannot read: is a directory, not a file");
  }
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    return Status(StatusCode::kIoError, path + ": cannot open: " + reason(errno));
  }
  // Regular files: size the buffer once. Others (pipes, devices): read chunks until EOF.
  std::uintmax_t expected = 0;
  const bool regular = st.type() == std::filesystem::file_type::regular;
  if (regular) {
    expected = std::filesystem::file_size(path, ec);
    if (ec) expected = 0;
  }
  std::size_t used = 0;
  bytes->resize(regular && expected > 0 ? static_cast<std::size_t>(expected) + 1 : kReadChunkBytes);
  for (;;) {
    if (used == bytes->size()) bytes->resize(bytes->size() * 2);
    errno = 0;
    const std::size_t got = std::fread(&(*bytes)[used], 1, bytes->size() - used, f);
    used += got;
    if (got == 0) break;
  }
  const bool read_error = std::ferror(f) != 0;
  const int read_errno = errno;
  std::fclose(f);
  if (read_error) {
    bytes->clear();
    return Status(StatusCode::kIoError, path + ": read failed after " + std::to_string(used) +
                                            " bytes: " + reason(read_errno));
  }
  bytes->resize(used);
  return Status::Ok();
}

FileWriter::~FileWriter() {
  if (file_ != nullptr) {
    std::fclose(file_);
    remove_partial(path_);
  }
}

Status FileWriter::open(const std::string& path) {
  path_ = path;
  if (path.empty()) return Status(StatusCode::kIoError, "cannot write: empty file name");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return Status(StatusCode::kIoError, path + ": cannot write: is a directory");
  }
  errno = 0;
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) {
    return Status(StatusCode::kIoError, path + ": cannot open for writing: " + reason(errno));
  }
  buffer_.reserve(kWriteChunkBytes);
  return Status::Ok();
}

void FileWriter::fail(const char* step, int error_number) {
  if (!error_.ok()) return;
  error_ = Status(StatusCode::kIoError, path_ + ": " + step + " failed: " + reason(error_number));
}

void FileWriter::flush_buffer() {
  if (buffer_.empty() || file_ == nullptr || !error_.ok()) return;
  errno = 0;
  const std::size_t put = std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
  if (put != buffer_.size()) fail("write", errno);
  buffer_.clear();
}

void FileWriter::append(std::string_view bytes) {
  if (file_ == nullptr || !error_.ok()) return;
  buffer_.append(bytes.data(), bytes.size());
  if (buffer_.size() >= kWriteChunkBytes) flush_buffer();
}

void FileWriter::append(const void* bytes, std::size_t size) {
  append(std::string_view(static_cast<const char*>(bytes), size));
}

Status FileWriter::finish() {
  if (file_ == nullptr) {
    if (error_.ok()) return Status(StatusCode::kIoError, path_ + ": file was not opened");
    return error_;
  }
  flush_buffer();
  errno = 0;
  if (error_.ok() && std::fflush(file_) != 0) fail("flush", errno);
  errno = 0;
  if (std::fclose(file_) != 0) fail("close", errno);
  file_ = nullptr;
  if (!error_.ok()) remove_partial(path_);
  return error_;
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
