// xyz_reader.cpp - reads XYZ / CSV / PTS text: one point per line, fields separated by blanks
// or by commas; every field must be a number and every line must have the same number of fields.
//
// Also tolerated:
//  - a UTF-8 byte-order mark at the start;
//  - blank lines, and comments: '#' starts a comment that runs to the end of the line;
//  - a header line of column names (no field is a number), only as the first non-comment line.
//    When it names x, y and z (in any case; CloudCompare's "//X" and quoted names too), those
//    columns are read, wherever they stand ("nx,ny,nz,x,y,z"); when it names none of them, the
//    first three columns are. Every data line must have as many fields as the header has names;
//  - a PTS point count: a single non-negative integer as the first non-comment line, which must
//    then equal the number of data lines.
// Without a header the first three fields are x y z. Refused, with the line, the column and the
// text seen, never guessed: a comma inside a blank-separated number (a decimal comma "1,5" or a
// thousands separator "5,632.500"), ';'-separated fields, any other non-numeric field.
// "nan"/"inf" fields are numbers: such points are dropped and counted, not errors.
// A line of more than kMaxFields fields (a header's names included) is refused with its count:
// it is not one point (x y z and at most 61 attributes), but points run together on a line.
#include <string>
#include <vector>

#include "formats.hpp"
#include "text_fields.hpp"
#include "text_scan.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

std::string quoted(std::string_view text) { return "'" + escape_for_message(text) + "'"; }

std::string at_line(std::size_t line) { return "line " + std::to_string(line) + ": "; }

// The most fields one line may hold: x, y, z and the attributes a point carries (colour, normal,
// intensity, curvature, time, ring... ), with room to spare.
constexpr std::size_t kMaxFields = 64;

Status too_many_fields(const Input& in, std::size_t ln, std::size_t n) {
  return parse_error(in, "line " + std::to_string(ln) + " has " + std::to_string(n) +
                             " fields, more than the " + std::to_string(kMaxFields) +
                             " a point can have: a text cloud holds one point per line "
                             "(x y z, then any attributes)");
}

std::string where(std::size_t line, std::size_t field, std::size_t column) {
  return "line " + std::to_string(line) + ", field " + std::to_string(field) + " (column " +
         std::to_string(column) + "): ";
}

// Which fields hold x, y, z and how many fields a data line has.
struct Layout {
  std::size_t xyz[3] = {0, 1, 2};  // 0-based field indices
  std::size_t columns = 0;         // fields per data line; 0 until the header or first data line
  std::size_t columns_line = 0;    // the line that fixed it
  bool from_header = false;
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

// Picks x, y, z among the header's names: all three by name, or none (the first three columns).
Status choose_columns(const Input& in, std::size_t ln, const std::vector<TextAt>& names,
                      Layout* layout) {
  static const char* const kAxes[3] = {"x", "y", "z"};
  bool found[3] = {false, false, false};
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string name = normalized_name(names[i].text);
    for (int axis = 0; axis < 3; ++axis) {
      if (name != kAxes[axis]) continue;
      if (found[axis]) {
        return parse_error(in, at_line(ln) + "the header names column '" + kAxes[axis] +
                                   "' twice (fields " + std::to_string(layout->xyz[axis] + 1) +
                                   " and " + std::to_string(i + 1) + ")");
      }
      found[axis] = true;
      layout->xyz[axis] = i;
    }
  }
  if (!found[0] && !found[1] && !found[2]) {
    for (std::size_t axis = 0; axis < 3; ++axis) layout->xyz[axis] = axis;
    return Status::Ok();
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (found[axis]) continue;
    return parse_error(in, at_line(ln) + "the header names some of x, y, z but no column '" +
                               kAxes[axis] + "': x, y and z are chosen by name (any case)");
  }
  return Status::Ok();
}

// The first content line may be a header of column names; if it is, fixes the layout.
Status try_header(const Input& in, std::size_t ln, std::string_view line, Layout* layout,
                  bool* is_header) {
  *is_header = false;
  const std::vector<TextAt> names = split_header_names(line);
  if (names.size() > kMaxFields) return too_many_fields(in, ln, names.size());
  double ignored = 0.0;
  for (const TextAt& name : names) {
    if (parse_double(name.text, &ignored) || !looks_like_name(name.text)) return Status::Ok();
  }
  *is_header = true;
  layout->columns = names.size();
  layout->columns_line = ln;
  layout->from_header = true;
  return choose_columns(in, ln, names, layout);
}

// A comma inside a blank-separated number: refused with the line, the column and the text.
Status check_comma_in_number(const Input& in, std::size_t ln, std::string_view line) {
  TextAt token;
  if (find_comma_in_blank_separated(line, &token)) {
    return parse_error(in, "line " + std::to_string(ln) + ", column " +
                               std::to_string(token.column) + ": " + quoted(token.text) +
                               " holds a comma while blanks separate the fields of the line: a "
                               "decimal comma ('1,5') or a thousands separator ('5,632.5') is "
                               "not read; write numbers with a '.' and no grouping");
  }
  return Status::Ok();
}

// ';' between fields (spreadsheets where ',' is the decimal separator): refused on every line.
Status check_semicolons(const Input& in, std::size_t ln, std::string_view line) {
  const std::size_t semicolon = line.find(';');
  if (semicolon != std::string_view::npos) {
    return parse_error(in, "line " + std::to_string(ln) + ", column " +
                               std::to_string(semicolon + 1) + ": " + quoted(line) +
                               " is separated by ';' (usually with decimal commas), which is not "
                               "read; separate fields with blanks or commas, decimals with '.'");
  }
  return Status::Ok();
}

// Checks a data line's field count against the header or the first data line.
Status check_field_count(const Input& in, std::size_t ln, std::string_view line, std::size_t n,
                         Layout* layout) {
  const std::string hint = line.find(',') == std::string_view::npos
                               ? ""
                               : " (a decimal comma or a thousands separator would split a "
                                 "number into two fields)";
  const std::string found = at_line(ln) + "found " + std::to_string(n) + " fields, but ";
  if (layout->from_header && n != layout->columns) {
    return parse_error(in, found + "the header (line " + std::to_string(layout->columns_line) +
                               ") names " + std::to_string(layout->columns) + " columns" + hint +
                               ": " + quoted(line));
  }
  if (n < 3) {
    return parse_error(in, at_line(ln) + "expected at least 3 fields (x y z), found " +
                               std::to_string(n) + ": " + quoted(line));
  }
  if (layout->columns == 0) {
    layout->columns = n;
    layout->columns_line = ln;
  } else if (n != layout->columns) {
    return parse_error(in, found + "line " + std::to_string(layout->columns_line) + " has " +
                               std::to_string(layout->columns) + hint + ": " + quoted(line));
  }
  return Status::Ok();
}

// Reads one data line: every field a number; x, y, z from the layout's columns.
Status read_row(const Input& in, std::size_t ln, std::string_view line, Layout* layout,
                double xyz[3]) {
  Status status = check_comma_in_number(in, ln, line);
  if (!status.ok()) return status;
  FieldSplitter fields(line);
  std::string_view field;
  while (fields.next(&field)) {
    if (fields.index() > kMaxFields) {
      while (fields.next(&field)) {
      }
      return too_many_fields(in, ln, fields.index());
    }
    const std::string at = where(ln, fields.index(), fields.column());
    double value = 0.0;
    if (field.empty()) return parse_error(in, at + "empty field between commas");
    if (!parse_double(field, &value)) {
      return parse_error(in, at + "expected a number, saw " + quoted(field));
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (fields.index() == layout->xyz[axis] + 1) xyz[axis] = value;
    }
  }
  return check_field_count(in, ln, line, fields.index(), layout);
}

}  // namespace

Status read_xyz(const Input& in, PointCloud* cloud, ReadReport* report) {
  cloud->clear();
  report->format = Format::kXyz;
  report->encoding = "ascii";
  PointSink sink(cloud);
  LineCursor cursor(in.data, in.size, utf8_bom_size(in.data, in.size));
  std::string_view raw;
  bool first_content_line = true;
  Layout layout;
  bool have_pts_count = false;
  std::uint64_t pts_count = 0;
  std::size_t pts_count_line = 0;
  std::size_t rows = 0;
  while (cursor.next(&raw)) {
    const std::size_t ln = cursor.line_number();
    const std::string_view line = trim(strip_comment(raw));
    if (line.empty()) continue;
    Status status = check_semicolons(in, ln, line);
    if (!status.ok()) return status;
    if (first_content_line) {
      first_content_line = false;
      bool is_header = false;
      status = try_header(in, ln, line, &layout, &is_header);
      if (!status.ok()) return status;
      if (is_header) continue;
      if (parse_uint64(line, &pts_count)) {  // a PTS point count
        have_pts_count = true;
        pts_count_line = ln;
        continue;
      }
    }
    double xyz[3] = {0.0, 0.0, 0.0};
    status = read_row(in, ln, line, &layout, xyz);
    if (!status.ok()) {
      cloud->clear();
      return status;
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
