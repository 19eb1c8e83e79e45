// text_fields.hpp - the fields of one line of a text cloud (XYZ / CSV / PTS), and the separator
// mix-ups that must be refused rather than guessed (private to ppcr_io).
//
// Fields are separated by blanks or by commas (with or without blanks around them). A comma inside
// a blank-separated field ("1,5 2,0 3,25", "5,632.500 1 2") is a decimal comma or a thousands
// separator: such lines are refused, never read by splitting the number at the comma.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

/// Splits a line (comment already removed) into fields separated by blanks and/or one comma.
class FieldSplitter {
 public:
  explicit FieldSplitter(std::string_view line) : line_(line) {}

  /// Next field; false at the end of the line. Two commas with nothing between them, a leading
  /// comma or a trailing comma give an empty field (which the reader rejects).
  bool next(std::string_view* field);
  /// 1-based index of the last field returned.
  std::size_t index() const { return index_; }
  /// 1-based character position of the last field returned.
  std::size_t column() const { return column_; }

 private:
  bool emit_empty(std::string_view* field, std::size_t at);

  std::string_view line_;
  std::size_t pos_ = 0;
  std::size_t index_ = 0;
  std::size_t column_ = 0;
  bool after_comma_ = false;
};

/// A piece of a line and its 1-based character position.
struct TextAt {
  std::string_view text;
  std::size_t column = 0;
};

/// If blanks separate the fields of this line (two neighbouring blank-separated tokens with no
/// comma between them) and a comma also stands inside a token, returns that token: a decimal
/// comma or a thousands separator. "1, 2, 3" and "1 ,2 ,3" are comma-separated and not reported.
bool find_comma_in_blank_separated(std::string_view line, TextAt* token);

/// The column names of a header line: split at commas if the line has one (names may then hold
/// blanks), else at blanks; each name trimmed.
std::vector<TextAt> split_header_names(std::string_view line);

/// A header name as compared: without CloudCompare's leading "//", without surrounding quotes,
/// in lower case ("//X" -> "x", "\"Y\"" -> "y").
std::string normalized_name(std::string_view name);

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
