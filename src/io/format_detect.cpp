// format_detect.cpp - picks a cloud format from a file name's extension or from its first bytes.
#include <cctype>
#include <string>

#include "formats.hpp"
#include "text_scan.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

// Content sniffing looks at no more than this many bytes of leading comment/blank lines.
constexpr std::size_t kMaxSniffBytes = 1 << 16;

bool starts_with(std::string_view text, std::string_view prefix) {
  return text.size() >= prefix.size() && text.substr(0, prefix.size()) == prefix;
}

// First field of a text line, split at blanks or a comma.
std::string_view first_field(std::string_view line) {
  line = trim(line);
  std::size_t end = 0;
  while (end < line.size() && !is_blank_char(line[end]) && line[end] != ',') ++end;
  return line.substr(0, end);
}

}  // namespace

Format format_from_extension_impl(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) {
    return Format::kAuto;
  }
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == "ply") return Format::kPly;
  if (ext == "pcd") return Format::kPcd;
  if (ext == "xyz" || ext == "txt" || ext == "csv" || ext == "pts") return Format::kXyz;
  if (ext == "bin") return Format::kKittiBin;
  if (ext == "png") return Format::kDepthPng;
  return Format::kAuto;
}

Format format_from_content(const char* data, std::size_t size) {
  const std::size_t bom = utf8_bom_size(data, size);
  const std::string_view all(data + bom, size - bom);
  if (starts_with(all, "ply\n") || starts_with(all, "ply\r\n")) return Format::kPly;
  if (starts_with(all, "\x89PNG\r\n\x1a\n")) return Format::kDepthPng;
  LineCursor cursor(data, size < kMaxSniffBytes ? size : kMaxSniffBytes, bom);
  std::string_view line;
  bool saw_names_line = false;
  while (cursor.next(&line)) {
    const std::string_view text = trim(line);
    if (text.empty()) continue;
    if (text[0] == '#') {
      if (starts_with(text, "# .PCD")) return Format::kPcd;
      continue;
    }
    const std::string_view first = first_field(text);
    if (!saw_names_line && (first == "VERSION" || first == "FIELDS")) return Format::kPcd;
    double ignored = 0.0;
    if (parse_double(first, &ignored)) return Format::kXyz;
    // A line of column names may precede the numbers of an XYZ/CSV file: look at one more line.
    if (saw_names_line) return Format::kAuto;
    saw_names_line = true;
  }
  return Format::kAuto;
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
