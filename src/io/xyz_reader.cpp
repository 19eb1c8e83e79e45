// xyz_reader.cpp - reads XYZ / CSV / PTS text: one point per line, fields separated by blanks
// and/or commas, the first three fields are x y z (more columns are allowed and skipped, but
// every field must be a number and every line must have the same number of fields).
//
// Also tolerated:
//  - blank lines, and comments: '#' starts a comment that runs to the end of the line;
//  - a header line of column names (no field is a number), only as the first non-comment line;
//  - a PTS point count: a single non-negative integer as the first non-comment line, which must
//    then equal the number of data lines.
// Any other non-numeric field is an error naming the line, the field and the text seen.
// "nan"/"inf" fields are numbers: such points are dropped and counted, not errors.
#include <string>

#include "formats.hpp"
#include "text_scan.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

std::string quoted(std::string_view text) { return "'" + escape_for_message(text) + "'"; }

// Splits a line (comment already removed) into fields separated by blanks and/or one comma.
class FieldSplitter {
 public:
  explicit FieldSplitter(std::string_view line) : line_(line) {}

  // Next field; false at the end of the line. Two commas with nothing between them, a leading
  // comma or a trailing comma give an empty field (which the reader rejects).
  bool next(std::string_view* field) {
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
  /// 1-based index of the last field returned.
  std::size_t index() const { return index_; }
  /// 1-based character position of the last field returned.
  std::size_t column() const { return column_; }

 private:
  std::string_view line_;
  std::size_t pos_ = 0;
  std::size_t index_ = 0;
  std::size_t column_ = 0;
  bool after_comma_ = false;

  bool emit_empty(std::string_view* field, std::size_t at) {
    *field = std::string_view();
    column_ = at + 1;
    ++index_;
    return true;
  }
};

// A column name: non-empty, and no control bytes (binary garbage is not taken for a header).
bool looks_like_name(std::string_view field) {
  if (field.empty()) return false;
  for (char c : field) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) return false;
  }
  return true;
}

std::string_view strip_comment(std::string_view line) {
  const std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

std::string where(std::size_t line, const FieldSplitter& fields) {
  return "line " + std::to_string(line) + ", field " + std::to_string(fields.index()) +
         " (character " + std::to_string(fields.column()) + "): ";
}

}  // namespace

Status read_xyz(const Input& in, PointCloud* cloud, ReadReport* report) {
  cloud->clear();
  report->format = Format::kXyz;
  report->encoding = "ascii";
  PointSink sink(cloud);
  LineCursor cursor(in.data, in.size);
  std::string_view raw;
  bool first_content_line = true;
  std::size_t columns = 0;       // fields per data line, fixed by the first data line
  std::size_t columns_line = 0;  // the line that fixed it
  bool have_pts_count = false;
  std::uint64_t pts_count = 0;
  std::size_t pts_count_line = 0;
  std::size_t rows = 0;
  while (cursor.next(&raw)) {
    const std::size_t ln = cursor.line_number();
    const std::string_view line = trim(strip_comment(raw));
    if (line.empty()) continue;
    const bool first = first_content_line;
    first_content_line = false;

    if (first) {
      // A header of column names, or a PTS point count?
      FieldSplitter probe(line);
      std::string_view field;
      std::size_t n = 0, names = 0;
      double ignored = 0.0;
      while (probe.next(&field)) {
        ++n;
        if (!parse_double(field, &ignored) && looks_like_name(field)) ++names;
      }
      if (names == n) continue;  // column names: tolerated on the first content line only
      std::uint64_t count = 0;
      if (n == 1 && parse_uint64(line, &count)) {
        have_pts_count = true;
        pts_count = count;
        pts_count_line = ln;
        continue;
      }
    }

    FieldSplitter fields(line);
    std::string_view field;
    double xyz[3] = {0.0, 0.0, 0.0};
    while (fields.next(&field)) {
      double value = 0.0;
      if (field.empty()) {
        return parse_error(in, where(ln, fields) + "empty field between commas");
      }
      if (!parse_double(field, &value)) {
        return parse_error(in, where(ln, fields) + "expected a number, saw " + quoted(field));
      }
      if (fields.index() <= 3) xyz[fields.index() - 1] = value;
    }
    const std::size_t n = fields.index();
    if (n < 3) {
      return parse_error(in, "line " + std::to_string(ln) +
                                 ": expected at least 3 fields (x y z), "
                                 "found " +
                                 std::to_string(n) + ": " + quoted(line));
    }
    if (columns == 0) {
      columns = n;
      columns_line = ln;
    } else if (n != columns) {
      return parse_error(in, "line " + std::to_string(ln) + ": found " + std::to_string(n) +
                                 " fields, but line " + std::to_string(columns_line) + " has " +
                                 std::to_string(columns));
    }
    sink.add(xyz[0], xyz[1], xyz[2]);
    ++rows;
  }
  if (have_pts_count && pts_count != rows) {
    cloud->clear();
    return parse_error(in, "line " + std::to_string(pts_count_line) + " announces " +
                               std::to_string(pts_count) + " points, the file holds " +
                               std::to_string(rows));
  }
  return finish_read(in, rows, sink, *cloud, report);
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
