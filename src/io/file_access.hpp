// file_access.hpp - reading a whole file into memory and writing one with checked stdio
// (private to ppcr_io). Neither throws nor prints; failures come back as a Status naming the path.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

/// Reads the whole file at `path` into *bytes. kIoError for a missing file, a directory, a file
/// that cannot be opened or read (the message names the path and the system's reason).
Status read_file_bytes(const std::string& path, std::string* bytes);

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
