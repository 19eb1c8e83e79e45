// file_access.cpp - whole-file reads and checked buffered writes (see file_access.hpp).
#include "file_access.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <filesystem>
#include <system_error>
#include <vector>

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
// A stream is read in pieces of this size (read_bounded).
constexpr std::size_t kStreamChunkBytes = std::size_t{16} << 20;

// How a file type is named in messages.
std::string type_name(std::filesystem::file_type type) {
  switch (type) {
    case std::filesystem::file_type::character:
      return "a character device";
    case std::filesystem::file_type::block:
      return "a block device";
    case std::filesystem::file_type::fifo:
      return "a pipe (FIFO)";
    case std::filesystem::file_type::socket:
      return "a socket";
    default:
      return "a file that is not a regular file";
  }
}

Status too_large(const std::string& path, const std::string& size, const ReadLimits& limits,
                 std::uint64_t limit) {
  return Status(StatusCode::kIoError, path + ": " + size + " bytes is too large for " +
                                          limits.kind + " (limit " + std::to_string(limit) +
                                          " bytes); not read");
}

struct BoundedRead {
  std::uint64_t used = 0;
  bool over_limit = false;  // more than the limit arrived (only limit + 1 bytes were read)
  bool error = false;
  int error_number = 0;
};

// Reads up to `size` bytes of f at *used into buffer; false when f gave fewer (its end, or an
// error: ferror tells).
bool read_some(std::FILE* f, char* buffer, std::size_t size, BoundedRead* r) {
  errno = 0;
  const std::size_t got = std::fread(buffer, 1, size, f);
  r->used += got;
  if (got < size) r->error_number = errno;
  return got == size;
}

// Reads f to EOF into *bytes, but never more than limit + 1 bytes. A regular file (`expected`,
// its size) is read into one buffer sized once, grown by doubling only if the file grows. A stream
// (expected 0: a pipe has no size) is read in chunks of kStreamChunkBytes kept apart until it ends,
// then moved into *bytes chunk by chunk, each released once copied: the resident peak is what was
// read plus one chunk, never a doubled buffer together with its old copy (on a stream that
// never ends: the limit plus one chunk).
BoundedRead read_bounded(std::FILE* f, std::uint64_t expected, std::uint64_t limit,
                         std::string* bytes) {
  const std::uint64_t cap = std::min<std::uint64_t>(limit, SIZE_MAX - 1) + 1;
  BoundedRead r;
  if (expected > 0) {
    bytes->resize(static_cast<std::size_t>(std::min(expected + 1, cap)));
    for (;;) {
      if (r.used == bytes->size()) {
        if (r.used >= cap) break;
        bytes->resize(static_cast<std::size_t>(std::min<std::uint64_t>(2 * r.used, cap)));
      }
      const std::size_t offset = static_cast<std::size_t>(r.used);
      if (!read_some(f, &(*bytes)[offset], bytes->size() - offset, &r)) break;
    }
    bytes->resize(static_cast<std::size_t>(r.used));
  } else {
    std::vector<std::string> chunks;
    while (r.used < cap) {
      std::string& chunk = chunks.emplace_back();
      chunk.resize(
          static_cast<std::size_t>(std::min<std::uint64_t>(kStreamChunkBytes, cap - r.used)));
      const std::uint64_t before = r.used;
      const bool full = read_some(f, chunk.data(), chunk.size(), &r);
      chunk.resize(static_cast<std::size_t>(r.used - before));
      if (!full) break;
    }
    bytes->clear();
    if (r.used <= limit) {
      bytes->reserve(static_cast<std::size_t>(r.used));
      for (std::string& chunk : chunks) {
        bytes->append(chunk);
        std::string().swap(chunk);
      }
    }
  }
  r.over_limit = r.used > limit;
  r.error = std::ferror(f) != 0;
  return r;
}

}  // namespace

Status read_file_bytes(const std::string& path, const ReadLimits& limits, std::string* bytes) {
  bytes->clear();
  if (path.empty()) return Status(StatusCode::kIoError, "empty file name");
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  const std::filesystem::file_type type = st.type();
  if (type == std::filesystem::file_type::not_found) {
    return Status(StatusCode::kIoError, path + ": cannot open: no such file");
  }
  if (type == std::filesystem::file_type::directory) {
    return Status(StatusCode::kIoError, path + ": cannot read: is a directory, not a file");
  }
  if (type == std::filesystem::file_type::character || type == std::filesystem::file_type::block) {
    return Status(StatusCode::kIoError, path + ": cannot read: it is " + type_name(type) +
                                            ", not a regular file (a device can give bytes "
                                            "without end); expected " +
                                            limits.kind);
  }
  const bool regular = type == std::filesystem::file_type::regular;
  const std::uint64_t limit = regular ? limits.max_regular_bytes : limits.max_stream_bytes;
  std::uint64_t expected = 0;
  if (regular) {
    expected = std::filesystem::file_size(path, ec);
    if (ec) expected = 0;
    if (expected > limit) return too_large(path, std::to_string(expected), limits, limit);
  }
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    return Status(StatusCode::kIoError, path + ": cannot open: " + reason(errno));
  }
  const BoundedRead got = read_bounded(f, expected, limit, bytes);
  std::fclose(f);
  if (got.error) {
    bytes->clear();
    return Status(StatusCode::kIoError, path + ": read failed after " + std::to_string(got.used) +
                                            " bytes: " + reason(got.error_number));
  }
  if (got.over_limit) {
    bytes->clear();
    if (regular) return too_large(path, "more than " + std::to_string(limit), limits, limit);
    return Status(StatusCode::kIoError,
                  path + ": " + type_name(type) + " gave more than " + std::to_string(limit) +
                      " bytes without ending, the limit for " + limits.kind + "; refused");
  }
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
