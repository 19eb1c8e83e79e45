// text_scan.cpp - bounded line/token scanning and number parsing (see text_scan.hpp).
#include "text_scan.hpp"

#include <charconv>
#include <cstring>
#include <system_error>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

bool LineCursor::next(std::string_view* line) {
  if (pos_ >= size_) return false;
  const char* start = data_ + pos_;
  const void* nl = std::memchr(start, '\n', size_ - pos_);
  std::size_t length;
  if (nl != nullptr) {
    length = static_cast<std::size_t>(static_cast<const char*>(nl) - start);
    terminated_ = true;
  } else {
    length = size_ - pos_;
    terminated_ = false;
  }
  line_offset_ = pos_;
  pos_ += length + (terminated_ ? 1 : 0);
  if (length > 0 && start[length - 1] == '\r') --length;
  *line = std::string_view(start, length);
  ++next_line_number_;
  return true;
}

bool Tokenizer::next(std::string_view* token) {
  while (pos_ < line_.size() && is_blank_char(line_[pos_])) ++pos_;
  if (pos_ >= line_.size()) return false;
  const std::size_t start = pos_;
  while (pos_ < line_.size() && !is_blank_char(line_[pos_])) ++pos_;
  *token = line_.substr(start, pos_ - start);
  column_ = start + 1;
  return true;
}

std::string_view trim(std::string_view line) {
  std::size_t b = 0;
  std::size_t e = line.size();
  while (b < e && is_blank_char(line[b])) ++b;
  while (e > b && is_blank_char(line[e - 1])) --e;
  return line.substr(b, e - b);
}

bool is_blank_line(std::string_view line) { return trim(line).empty(); }

bool parse_double(std::string_view token, double* value) {
  const char* first = token.data();
  const char* last = token.data() + token.size();
  // std::from_chars takes '-' but not '+'; accept one '+' if a number (not another sign) follows.
  if (first != last && *first == '+') {
    ++first;
    if (first == last || *first == '-' || *first == '+') return false;
  }
  if (first == last) return false;
  double parsed = 0.0;
  const std::from_chars_result result =
      std::from_chars(first, last, parsed, std::chars_format::general);
  if (result.ec != std::errc() || result.ptr != last) return false;
  *value = parsed;
  return true;
}

bool parse_uint64(std::string_view token, std::uint64_t* value) {
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (first != last && *first == '+') ++first;
  if (first == last || *first < '0' || *first > '9') return false;
  std::uint64_t parsed = 0;
  const std::from_chars_result result = std::from_chars(first, last, parsed, 10);
  if (result.ec != std::errc() || result.ptr != last) return false;
  *value = parsed;
  return true;
}

std::string escape_for_message(std::string_view bytes, std::size_t max_chars) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  const std::size_t n = bytes.size() < max_chars ? bytes.size() : max_chars;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(bytes[i]);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\\') {
      out += "\\\\";
    } else if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 0xf];
    }
  }
  if (bytes.size() > n) out += "...";
  return out;
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
