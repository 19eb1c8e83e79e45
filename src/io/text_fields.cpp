// text_fields.cpp - splitting a text cloud's line into fields (see text_fields.hpp).
#include "text_fields.hpp"

#include <cctype>

#include "text_scan.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

bool FieldSplitter::next(std::string_view* field) {
  for (;;) {
    while (pos_ < line_.size() && is_blank_char(line_[pos_])) ++pos_;
    if (pos_ >= line_.size()) {
      if (!after_comma_) return false;
      after_comma_ = false;  // "1,2,3," : an empty last field
      return emit_empty(field, pos_);
    }
    if (line_[pos_] != ',') break;
    const std::size_t comma = pos_++;
    if (after_comma_ || index_ == 0) {  // ",," or a leading ','
      after_comma_ = true;
      return emit_empty(field, comma);
    }
    after_comma_ = true;  // the separator after a field
  }
  const std::size_t start = pos_;
  while (pos_ < line_.size() && !is_blank_char(line_[pos_]) && line_[pos_] != ',') ++pos_;
  after_comma_ = false;
  *field = line_.substr(start, pos_ - start);
  column_ = start + 1;
  ++index_;
  return true;
}

bool FieldSplitter::emit_empty(std::string_view* field, std::size_t at) {
  *field = std::string_view();
  column_ = at + 1;
  ++index_;
  return true;
}

bool find_comma_in_blank_separated(std::string_view line, TextAt* token) {
  Tokenizer tokens(line);
  std::string_view t, previous;
  bool blank_separated = false;
  bool found = false;
  while (tokens.next(&t)) {
    if (!previous.empty() && previous.back() != ',' && t.front() != ',') blank_separated = true;
    if (!found && t != "," && t.find(',') != std::string_view::npos) {
      found = true;
      *token = TextAt{t, tokens.column()};
    }
    previous = t;
  }
  return blank_separated && found;
}

std::vector<TextAt> split_header_names(std::string_view line) {
  std::vector<TextAt> names;
  if (line.find(',') == std::string_view::npos) {
    Tokenizer tokens(line);
    std::string_view t;
    while (tokens.next(&t)) names.push_back(TextAt{t, tokens.column()});
    return names;
  }
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
    const std::string_view raw = line.substr(start, end - start);
    const std::string_view name = trim(raw);
    const std::size_t lead = name.empty() ? 0 : static_cast<std::size_t>(name.data() - raw.data());
    names.push_back(TextAt{name, start + lead + 1});
    if (comma == std::string_view::npos) return names;
    start = comma + 1;
  }
}

std::string normalized_name(std::string_view name) {
  if (name.size() >= 2 && name.substr(0, 2) == "//") name = trim(name.substr(2));
  if (name.size() >= 2 && (name.front() == '"' || name.front() == '\'') &&
      name.back() == name.front()) {
    name = trim(name.substr(1, name.size() - 2));
  }
  std::string out(name);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
