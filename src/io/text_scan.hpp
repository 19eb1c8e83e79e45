// text_scan.hpp - bounded scanning of text held in memory (private to ppcr_io).
//
// Everything here works on [begin, end) ranges that need NOT be NUL-terminated (a file's bytes,
// or a fuzzer's buffer): nothing reads past `end`. Numbers are parsed with std::from_chars, which
// is locale-independent and bounded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

/// Walks a buffer line by line. A line ends at '\n'; a '\r' just before it (CRLF) is not part of
/// the line. The last line need not end with '\n'.
class LineCursor {
 public:
  LineCursor(const char* data, std::size_t size, std::size_t start_offset = 0,
             std::size_t first_line_number = 1)
      : data_(data), size_(size), pos_(start_offset), next_line_number_(first_line_number) {}

  /// Gets the next line (without its terminator). False at the end of the buffer.
  bool next(std::string_view* line);

  /// 1-based number of the line returned by the last next().
  std::size_t line_number() const { return next_line_number_ - 1; }
  /// Byte offset where the line returned by the last next() starts.
  std::size_t line_offset() const { return line_offset_; }
  /// Byte offset just after the last returned line's terminator (where the next line starts).
  std::size_t offset() const { return pos_; }
  /// True if the last returned line was terminated by '\n' (false: it ran to the end of data).
  bool last_line_terminated() const { return terminated_; }

 private:
  const char* data_;
  std::size_t size_;
  std::size_t pos_;
  std::size_t next_line_number_;
  std::size_t line_offset_ = 0;
  bool terminated_ = false;
};

/// Length of a UTF-8 byte-order mark (EF BB BF) at the start of the data: 3, or 0 if there is
/// none. Editors on Windows write one at the start of text files; every reader skips it.
inline std::size_t utf8_bom_size(const char* data, std::size_t size) {
  return size >= 3 && static_cast<unsigned char>(data[0]) == 0xEF &&
                 static_cast<unsigned char>(data[1]) == 0xBB &&
                 static_cast<unsigned char>(data[2]) == 0xBF
             ? 3
             : 0;
}

/// True for ' ', '\t', '\r', '\v', '\f' (the separators inside a line).
inline bool is_blank_char(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Splits a line into tokens separated by blanks. next() returns false when no token is left.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view line) : line_(line) {}
  bool next(std::string_view* token);
  /// 1-based column (character position in the line) of the token returned by the last next().
  std::size_t column() const { return column_; }
  /// The rest of the line after the last token (blanks included).
  std::string_view rest() const { return line_.substr(pos_); }

 private:
  std::string_view line_;
  std::size_t pos_ = 0;
  std::size_t column_ = 0;
};

/// The line without leading and trailing blanks.
std::string_view trim(std::string_view line);

/// True if the line holds only blanks.
bool is_blank_line(std::string_view line);

/// Parses a whole token as a double: an optional sign ('+' or '-'), decimal or scientific
/// notation, or inf/infinity/nan (any case), which give non-finite values. False if the token is
/// not entirely a number or its magnitude is outside double's range (e.g. "1e400", "1e-400").
bool parse_double(std::string_view token, double* value);

/// Parses a whole token as a non-negative decimal integer (digits only, optional leading '+').
/// False for signs, fractions, garbage, or values above UINT64_MAX.
bool parse_uint64(std::string_view token, std::uint64_t* value);

/// Shows up to max_chars bytes for an error message, printable ASCII as is and everything else
/// escaped (\n, \r, \t, \xNN); "..." is appended when the text was cut.
std::string escape_for_message(std::string_view bytes, std::size_t max_chars = 40);

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
