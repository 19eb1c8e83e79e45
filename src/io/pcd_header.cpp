// pcd_header.cpp - parses the header of a PCD file (see pcd_header.hpp).
#include "pcd_header.hpp"

#include <string>
#include <string_view>
#include <vector>

#include "text_scan.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

const char* data_name(PcdData d) {
  switch (d) {
    case PcdData::kAscii:
      return "ascii";
    case PcdData::kBinary:
      return "binary";
    case PcdData::kBinaryCompressed:
      return "binary_compressed";
  }
  return "?";
}

namespace {

std::string at_line(std::size_t line) { return "line " + std::to_string(line) + ": "; }

std::string quoted(std::string_view text) { return "'" + escape_for_message(text) + "'"; }

// Reads the rest of a header line as a list of tokens.
std::vector<std::string_view> rest_tokens(Tokenizer* tokens) {
  std::vector<std::string_view> out;
  std::string_view t;
  while (tokens->next(&t)) out.push_back(t);
  return out;
}

Status parse_single_count(const Input& in, std::size_t ln, std::string_view keyword,
                          Tokenizer* tokens, std::uint64_t* value) {
  const std::vector<std::string_view> values = rest_tokens(tokens);
  if (values.size() != 1) {
    return parse_error(in, at_line(ln) + std::string(keyword) + " expects one value, found " +
                               std::to_string(values.size()));
  }
  if (!parse_uint64(values[0], value)) {
    const bool negative = !values[0].empty() && values[0][0] == '-';
    return parse_error(
        in, at_line(ln) + std::string(keyword) + " " + quoted(values[0]) +
                (negative ? " is negative" : " is not a non-negative integer below 2^64"));
  }
  return Status::Ok();
}

// The header's lines as read, before they are checked against each other.
struct RawHeader {
  bool have_data = false, have_size = false, have_type = false, have_count = false;
  bool have_width = false, have_height = false, have_points = false, have_fields = false;
  std::vector<std::string_view> sizes, types, counts;
  std::size_t content_lines = 0;
};

Status parse_version(const Input& in, std::size_t ln, std::string_view text, Tokenizer* tokens,
                     PcdHeader* h) {
  if (h->version_line != 0) return parse_error(in, at_line(ln) + "second VERSION line");
  h->version_line = ln;
  const std::vector<std::string_view> v = rest_tokens(tokens);
  static const char* const kKnown[] = {"0.7", ".7", "0.6", ".6", "0.5", ".5", "0.7.0"};
  bool known = false;
  for (const char* k : kKnown) known = known || (v.size() == 1 && v[0] == k);
  if (!known) {
    return parse_error(in, at_line(ln) + "unsupported PCD VERSION " + quoted(text.substr(7)) +
                               " (expected 0.7, .6 or .5)");
  }
  return Status::Ok();
}

Status parse_viewpoint(const Input& in, std::size_t ln, std::string_view text, Tokenizer* tokens,
                       PcdHeader* h) {
  if (h->viewpoint_line != 0) return parse_error(in, at_line(ln) + "second VIEWPOINT line");
  h->viewpoint_line = ln;
  const std::vector<std::string_view> v = rest_tokens(tokens);
  double ignored = 0.0;
  bool numbers = v.size() == 7;
  for (std::string_view t : v) numbers = numbers && parse_double(t, &ignored);
  if (!numbers) {
    return parse_error(in, at_line(ln) +
                               "VIEWPOINT expects 7 numbers (tx ty tz qw qx qy qz), saw " +
                               quoted(text.substr(9)));
  }
  return Status::Ok();
}

Status parse_data_line(const Input& in, std::size_t ln, std::string_view text, Tokenizer* tokens,
                       PcdHeader* h) {
  const std::vector<std::string_view> v = rest_tokens(tokens);
  if (v.size() == 1 && v[0] == "ascii") {
    h->data = PcdData::kAscii;
  } else if (v.size() == 1 && v[0] == "binary") {
    h->data = PcdData::kBinary;
  } else if (v.size() == 1 && v[0] == "binary_compressed") {
    h->data = PcdData::kBinaryCompressed;
  } else {
    return parse_error(in, at_line(ln) + "unknown DATA type " + quoted(text.substr(4)) +
                               " (expected ascii, binary or binary_compressed)");
  }
  h->data_line = ln;
  return Status::Ok();
}

// Keeps the values of a SIZE, TYPE or COUNT line, checked later against FIELDS.
Status keep_list(const Input& in, std::size_t ln, std::string_view keyword, Tokenizer* tokens,
                 bool* seen, std::size_t* line, std::vector<std::string_view>* values) {
  if (*seen) return parse_error(in, at_line(ln) + "second " + std::string(keyword) + " line");
  *seen = true;
  *line = ln;
  *values = rest_tokens(tokens);
  return Status::Ok();
}

// Reads a WIDTH, HEIGHT or POINTS line.
Status keep_count(const Input& in, std::size_t ln, std::string_view keyword, Tokenizer* tokens,
                  bool* seen, std::size_t* line, std::uint64_t* value) {
  if (*seen) return parse_error(in, at_line(ln) + "second " + std::string(keyword) + " line");
  Status s = parse_single_count(in, ln, keyword, tokens, value);
  if (!s.ok()) return s;
  *seen = true;
  *line = ln;
  return Status::Ok();
}

Status parse_fields_line(const Input& in, std::size_t ln, Tokenizer* tokens, RawHeader* raw,
                         PcdHeader* h) {
  if (raw->have_fields) return parse_error(in, at_line(ln) + "second FIELDS line");
  raw->have_fields = true;
  h->fields_line = ln;
  for (std::string_view name : rest_tokens(tokens)) {
    PcdField f;
    f.name = std::string(name);
    h->fields.push_back(std::move(f));
  }
  if (h->fields.empty()) return parse_error(in, at_line(ln) + "FIELDS names no field");
  return Status::Ok();
}

// One header line (not blank, not a comment), dispatched on its keyword.
Status parse_header_line(const Input& in, std::size_t ln, std::string_view text, RawHeader* raw,
                         PcdHeader* h) {
  Tokenizer tokens(text);
  std::string_view keyword;
  tokens.next(&keyword);
  if (keyword == "VERSION") return parse_version(in, ln, text, &tokens, h);
  if (keyword == "FIELDS" || keyword == "COLUMNS")
    return parse_fields_line(in, ln, &tokens, raw, h);
  if (keyword == "SIZE") {
    return keep_list(in, ln, keyword, &tokens, &raw->have_size, &h->size_line, &raw->sizes);
  }
  if (keyword == "TYPE") {
    return keep_list(in, ln, keyword, &tokens, &raw->have_type, &h->type_line, &raw->types);
  }
  if (keyword == "COUNT") {
    return keep_list(in, ln, keyword, &tokens, &raw->have_count, &h->count_line, &raw->counts);
  }
  if (keyword == "WIDTH") {
    return keep_count(in, ln, keyword, &tokens, &raw->have_width, &h->width_line, &h->width);
  }
  if (keyword == "HEIGHT") {
    return keep_count(in, ln, keyword, &tokens, &raw->have_height, &h->height_line, &h->height);
  }
  if (keyword == "POINTS") {
    return keep_count(in, ln, keyword, &tokens, &raw->have_points, &h->points_line, &h->points);
  }
  if (keyword == "VIEWPOINT") return parse_viewpoint(in, ln, text, &tokens, h);
  if (keyword == "DATA") {
    Status s = parse_data_line(in, ln, text, &tokens, h);
    raw->have_data = s.ok();
    return s;
  }
  if (raw->content_lines == 1) {
    return parse_error(
        in, at_line(ln) + "not a PCD header: expected VERSION or FIELDS, saw " + quoted(text));
  }
  return parse_error(in, at_line(ln) + "unknown PCD header keyword " + quoted(keyword) +
                             " (expected VERSION FIELDS SIZE TYPE COUNT WIDTH HEIGHT "
                             "VIEWPOINT POINTS DATA)");
}

// Reads the header lines up to DATA (a UTF-8 byte-order mark before them is skipped) and sets
// where the data start.
Status read_header_lines(const Input& in, RawHeader* raw, PcdHeader* h) {
  LineCursor cursor(in.data, in.size, utf8_bom_size(in.data, in.size));
  std::string_view line;
  while (!raw->have_data && cursor.next(&line)) {
    const std::string_view text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    ++raw->content_lines;
    Status s = parse_header_line(in, cursor.line_number(), text, raw, h);
    if (!s.ok()) return s;
  }
  if (!raw->have_data) {
    return parse_error(in, "header has no DATA line (the file ends at byte " +
                               std::to_string(in.size) + ", line " +
                               std::to_string(cursor.line_number()) + ")");
  }
  h->body_offset = cursor.offset();
  h->body_first_line = cursor.line_number() + 1;
  return Status::Ok();
}

// Checks SIZE, TYPE and COUNT against FIELDS (one entry per field) and sets each field's type.
Status resolve_fields(const Input& in, const RawHeader& raw, PcdHeader* h) {
  if (!raw.have_fields) return parse_error(in, "header has no FIELDS line");
  const std::size_t n = h->fields.size();
  if (!raw.have_size) return parse_error(in, "header has no SIZE line");
  auto length_mismatch = [&](const char* what, std::size_t line_no, std::size_t found) {
    return parse_error(in, at_line(line_no) + what + " lists " + std::to_string(found) +
                               " entries but FIELDS (line " + std::to_string(h->fields_line) +
                               ") names " + std::to_string(n));
  };
  if (raw.sizes.size() != n) return length_mismatch("SIZE", h->size_line, raw.sizes.size());
  if (raw.have_type && raw.types.size() != n) {
    return length_mismatch("TYPE", h->type_line, raw.types.size());
  }
  if (raw.have_count && raw.counts.size() != n) {
    return length_mismatch("COUNT", h->count_line, raw.counts.size());
  }
  for (std::size_t i = 0; i < n; ++i) {
    PcdField& f = h->fields[i];
    if (!parse_uint64(raw.sizes[i], &f.size)) {
      return parse_error(in, at_line(h->size_line) + "SIZE of field '" + f.name + "' is " +
                                 quoted(raw.sizes[i]) + ", expected 1, 2, 4 or 8");
    }
    if (raw.have_type) {
      if (raw.types[i].size() != 1) {
        return parse_error(in, at_line(h->type_line) + "TYPE of field '" + f.name + "' is " +
                                   quoted(raw.types[i]) + ", expected F, I or U");
      }
      f.type = raw.types[i][0];
    }
    if (!pcd_scalar_type(f.type, f.size, &f.scalar)) {
      return parse_error(in, at_line(raw.have_type ? h->type_line : h->size_line) + "field '" +
                                 f.name + "' has TYPE " + std::string(1, f.type) + " SIZE " +
                                 std::to_string(f.size) +
                                 ", expected F 4/8, I 1/2/4/8 or U 1/2/4/8");
    }
    if (raw.have_count && (!parse_uint64(raw.counts[i], &f.count) || f.count == 0)) {
      return parse_error(in, at_line(h->count_line) + "COUNT of field '" + f.name + "' is " +
                                 quoted(raw.counts[i]) + ", expected a positive integer");
    }
  }
  return Status::Ok();
}

// Finds the fields x, y and z: each exactly once.
Status find_xyz_fields(const Input& in, PcdHeader* h) {
  static const char* const kAxes[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    bool found = false;
    for (std::size_t i = 0; i < h->fields.size(); ++i) {
      if (h->fields[i].name != kAxes[axis]) continue;
      if (found) {
        return parse_error(
            in, at_line(h->fields_line) + "field '" + kAxes[axis] + "' appears twice in FIELDS");
      }
      found = true;
      h->xyz_field[axis] = i;
    }
    if (!found) {
      return parse_error(in, at_line(h->fields_line) + "FIELDS has no field '" + kAxes[axis] + "'");
    }
  }
  return Status::Ok();
}

// Point count: WIDTH x HEIGHT, which POINTS (if given) must equal.
Status resolve_point_count(const Input& in, const RawHeader& raw, PcdHeader* h) {
  if (!raw.have_width) {
    if (!raw.have_points) return parse_error(in, "header has neither WIDTH nor POINTS");
    h->width = h->points;
    h->height = 1;
  }
  if (!checked_mul(h->width, h->height, &h->num_points)) {
    return parse_error(in, at_line(h->width_line) + "WIDTH x HEIGHT = " + std::to_string(h->width) +
                               " x " + std::to_string(h->height) + " overflows");
  }
  if (raw.have_points && h->points != h->num_points) {
    return parse_error(in, at_line(h->points_line) + "POINTS " + std::to_string(h->points) +
                               " disagrees with WIDTH x HEIGHT = " + std::to_string(h->width) +
                               " x " + std::to_string(h->height) + " = " +
                               std::to_string(h->num_points));
  }
  return Status::Ok();
}

}  // namespace

Status parse_pcd_header(const Input& in, PcdHeader* h) {
  RawHeader raw;
  Status s = read_header_lines(in, &raw, h);
  if (s.ok()) s = resolve_fields(in, raw, h);
  if (s.ok()) s = find_xyz_fields(in, h);
  if (s.ok()) s = resolve_point_count(in, raw, h);
  return s;
}

bool point_bytes(const PcdHeader& h, bool include_padding, std::uint64_t* bytes) {
  std::uint64_t total = 0;
  for (const PcdField& f : h.fields) {
    if (f.is_padding() && !include_padding) continue;
    std::uint64_t field_bytes = 0;
    if (!checked_mul(f.size, f.count, &field_bytes) || !checked_add(total, field_bytes, &total)) {
      return false;
    }
  }
  *bytes = total;
  return true;
}

bool point_values(const PcdHeader& h, bool include_padding, std::uint64_t* values) {
  std::uint64_t total = 0;
  for (const PcdField& f : h.fields) {
    if (f.is_padding() && !include_padding) continue;
    if (!checked_add(total, f.count, &total)) return false;
  }
  *values = total;
  return true;
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
