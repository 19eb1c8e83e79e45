// file_access.hpp - reading a whole file into memory and writing one with checked stdio
// (private to ppcr_io). Neither throws nor prints; failures come back as a Status naming the path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

/// How much read_file_bytes may read, and what the file is for (in messages).
struct ReadLimits {
  std::uint64_t max_regular_bytes;  // a larger regular file is refused before any read
  std::uint64_t max_stream_bytes;   // a pipe (FIFO, socket) is read up to this many bytes
  const char* kind;                 // "a point cloud", "a 4x4 matrix"
};

/// Reads the whole file at `path` into *bytes. kIoError for a missing file, a directory, a file
/// that cannot be opened or read (the message names the path and the system's reason).
/// Never reads without bound: a regular file's size is checked against the limit before reading
/// (and the read stops there if the file grows meanwhile); a device (/dev/zero, /dev/urandom, a
/// terminal) is refused by its type; a pipe is read until EOF or until it passes the limit,
/// which is then refused. Limits give kIoError naming the path, the size and the limit.
Status read_file_bytes(const std::string& path, const ReadLimits& limits, std::string* bytes);

/// A file opened for writing, with its output collected in a buffer and every stdio call checked.
/// Usage: open(), append()..., finish(). The first failure is kept and returned by finish();
/// a file whose writing failed is removed. The destructor closes (and removes) an unfinished file.
class FileWriter {
 public:
  FileWriter() = default;
  ~FileWriter();
  FileWriter(const FileWriter&) = delete;
  FileWriter& operator=(const FileWriter&) = delete;

  Status open(const std::string& path);
  void append(std::string_view bytes);
  void append(const void* bytes, std::size_t size);
  /// Flushes, closes and reports: Ok, or kIoError naming the path and the failing step.
  Status finish();

 private:
  void flush_buffer();
  void fail(const char* step, int error_number);

  std::FILE* file_ = nullptr;
  std::string path_;
  std::string buffer_;
  Status error_;
};

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
