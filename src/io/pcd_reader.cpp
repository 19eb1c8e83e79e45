// pcd_reader.cpp - reads the x y z fields of a PCD file (v0.7, and v.5/v.6 headers), DATA ascii,
// binary or binary_compressed.
//
// Header: '#' comment lines, VERSION, FIELDS (or COLUMNS), SIZE, TYPE (default F), COUNT
// (default 1), WIDTH, HEIGHT (default 1), VIEWPOINT (optional, 7 numbers, not applied to the
// points), POINTS (default WIDTH*HEIGHT, else must equal it), DATA (last). x, y, z are found by
// name and may have any TYPE/SIZE (F4 F8 I1..I8 U1..U8) and COUNT (the first value is used); all
// other fields, whatever their COUNT, are skipped. Organized clouds (HEIGHT > 1) are read row
// after row; their NaN padding points are dropped and counted like any non-finite point.
//
// binary: POINTS records of the packed field layout (array of structures), little endian.
// binary_compressed: uint32 compressed size, uint32 uncompressed size (little endian), then LZF
// data that decompresses to the fields in structure-of-arrays order (all x, then all y, ...).
// As written by PCL, padding fields named "_" are absent from that data; data that include them
// (uncompressed size = POINTS x full point size) are accepted too.
#include <lzf.h>

#include <memory>
#include <string>
#include <vector>

#include "formats.hpp"
#include "scalar_type.hpp"
#include "text_scan.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

struct PcdField {
  std::string name;
  std::uint64_t size = 0;   // bytes per value
  char type = 'F';          // F, I or U
  std::uint64_t count = 1;  // values per point
  ScalarType scalar = ScalarType::kFloat32;
  bool is_padding() const { return name == "_"; }
};

enum class PcdData { kAscii, kBinary, kBinaryCompressed };

struct PcdHeader {
  std::vector<PcdField> fields;
  std::size_t fields_line = 0, size_line = 0, type_line = 0, count_line = 0;
  std::size_t width_line = 0, height_line = 0, points_line = 0, version_line = 0;
  std::size_t viewpoint_line = 0, data_line = 0;
  std::uint64_t width = 0, height = 1, points = 0;
  std::uint64_t num_points = 0;  // WIDTH x HEIGHT, checked against POINTS
  PcdData data = PcdData::kAscii;
  std::size_t body_offset = 0;      // first byte after the DATA line
  std::size_t body_first_line = 0;  // line number of the first body line (ascii)
  std::size_t xyz_field[3] = {0, 0, 0};
};

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

Status parse_header(const Input& in, PcdHeader* h) {
  LineCursor cursor(in.data, in.size);
  std::string_view line;
  bool have_data = false, have_size = false, have_type = false, have_count = false;
  bool have_width = false, have_height = false, have_points = false, have_fields = false;
  std::vector<std::string_view> sizes, types, counts;
  std::size_t content_lines = 0;
  while (cursor.next(&line)) {
    const std::size_t ln = cursor.line_number();
    const std::string_view text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    ++content_lines;
    Tokenizer tokens(text);
    std::string_view keyword;
    tokens.next(&keyword);
    auto duplicate = [&](bool seen) {
      return seen ? parse_error(in, at_line(ln) + "second " + std::string(keyword) + " line")
                  : Status::Ok();
    };
    if (keyword == "VERSION") {
      if (h->version_line != 0) return duplicate(true);
      h->version_line = ln;
      const std::vector<std::string_view> v = rest_tokens(&tokens);
      static const char* const kKnown[] = {"0.7", ".7", "0.6", ".6", "0.5", ".5", "0.7.0"};
      bool known = false;
      for (const char* k : kKnown) known = known || (v.size() == 1 && v[0] == k);
      if (!known) {
        return parse_error(in, at_line(ln) + "unsupported PCD VERSION " + quoted(text.substr(7)) +
                                   " (expected 0.7, .6 or .5)");
      }
    } else if (keyword == "FIELDS" || keyword == "COLUMNS") {
      Status s = duplicate(have_fields);
      if (!s.ok()) return s;
      have_fields = true;
      h->fields_line = ln;
      for (std::string_view name : rest_tokens(&tokens)) {
        PcdField f;
        f.name = std::string(name);
        h->fields.push_back(std::move(f));
      }
      if (h->fields.empty()) return parse_error(in, at_line(ln) + "FIELDS names no field");
    } else if (keyword == "SIZE") {
      Status s = duplicate(have_size);
      if (!s.ok()) return s;
      have_size = true;
      h->size_line = ln;
      sizes = rest_tokens(&tokens);
    } else if (keyword == "TYPE") {
      Status s = duplicate(have_type);
      if (!s.ok()) return s;
      have_type = true;
      h->type_line = ln;
      types = rest_tokens(&tokens);
    } else if (keyword == "COUNT") {
      Status s = duplicate(have_count);
      if (!s.ok()) return s;
      have_count = true;
      h->count_line = ln;
      counts = rest_tokens(&tokens);
    } else if (keyword == "WIDTH") {
      Status s = duplicate(have_width);
      if (s.ok()) s = parse_single_count(in, ln, keyword, &tokens, &h->width);
      if (!s.ok()) return s;
      have_width = true;
      h->width_line = ln;
    } else if (keyword == "HEIGHT") {
      Status s = duplicate(have_height);
      if (s.ok()) s = parse_single_count(in, ln, keyword, &tokens, &h->height);
      if (!s.ok()) return s;
      have_height = true;
      h->height_line = ln;
    } else if (keyword == "POINTS") {
      Status s = duplicate(have_points);
      if (s.ok()) s = parse_single_count(in, ln, keyword, &tokens, &h->points);
      if (!s.ok()) return s;
      have_points = true;
      h->points_line = ln;
    } else if (keyword == "VIEWPOINT") {
      Status s = duplicate(h->viewpoint_line != 0);
      if (!s.ok()) return s;
      h->viewpoint_line = ln;
      const std::vector<std::string_view> v = rest_tokens(&tokens);
      double ignored = 0.0;
      bool numbers = v.size() == 7;
      for (std::string_view t : v) numbers = numbers && parse_double(t, &ignored);
      if (!numbers) {
        return parse_error(in, at_line(ln) +
                                   "VIEWPOINT expects 7 numbers (tx ty tz qw qx qy qz), saw " +
                                   quoted(text.substr(9)));
      }
    } else if (keyword == "DATA") {
      const std::vector<std::string_view> v = rest_tokens(&tokens);
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
      have_data = true;
      break;
    } else {
      if (content_lines == 1) {
        return parse_error(
            in, at_line(ln) + "not a PCD header: expected VERSION or FIELDS, saw " + quoted(text));
      }
      return parse_error(in, at_line(ln) + "unknown PCD header keyword " + quoted(keyword) +
                                 " (expected VERSION FIELDS SIZE TYPE COUNT WIDTH HEIGHT "
                                 "VIEWPOINT POINTS DATA)");
    }
  }
  if (!have_data) {
    return parse_error(in, "header has no DATA line (the file ends at byte " +
                               std::to_string(in.size) + ", line " +
                               std::to_string(cursor.line_number()) + ")");
  }
  h->body_offset = cursor.offset();
  h->body_first_line = cursor.line_number() + 1;

  // Fields: SIZE, TYPE, COUNT must list one entry per field.
  if (!have_fields) return parse_error(in, "header has no FIELDS line");
  const std::size_t n = h->fields.size();
  if (!have_size) return parse_error(in, "header has no SIZE line");
  auto length_mismatch = [&](const char* what, std::size_t line_no, std::size_t found) {
    return parse_error(in, at_line(line_no) + what + " lists " + std::to_string(found) +
                               " entries but FIELDS (line " + std::to_string(h->fields_line) +
                               ") names " + std::to_string(n));
  };
  if (sizes.size() != n) return length_mismatch("SIZE", h->size_line, sizes.size());
  if (have_type && types.size() != n) return length_mismatch("TYPE", h->type_line, types.size());
  if (have_count && counts.size() != n) {
    return length_mismatch("COUNT", h->count_line, counts.size());
  }
  for (std::size_t i = 0; i < n; ++i) {
    PcdField& f = h->fields[i];
    if (!parse_uint64(sizes[i], &f.size)) {
      return parse_error(in, at_line(h->size_line) + "SIZE of field '" + f.name + "' is " +
                                 quoted(sizes[i]) + ", expected 1, 2, 4 or 8");
    }
    if (have_type) {
      if (types[i].size() != 1) {
        return parse_error(in, at_line(h->type_line) + "TYPE of field '" + f.name + "' is " +
                                   quoted(types[i]) + ", expected F, I or U");
      }
      f.type = types[i][0];
    }
    if (!pcd_scalar_type(f.type, f.size, &f.scalar)) {
      return parse_error(in, at_line(have_type ? h->type_line : h->size_line) + "field '" + f.name +
                                 "' has TYPE " + std::string(1, f.type) + " SIZE " +
                                 std::to_string(f.size) +
                                 ", expected F 4/8, I 1/2/4/8 or U 1/2/4/8");
    }
    if (have_count && (!parse_uint64(counts[i], &f.count) || f.count == 0)) {
      return parse_error(in, at_line(h->count_line) + "COUNT of field '" + f.name + "' is " +
                                 quoted(counts[i]) + ", expected a positive integer");
    }
  }
  static const char* const kAxes[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    bool found = false;
    for (std::size_t i = 0; i < n; ++i) {
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

  // Point count: WIDTH x HEIGHT, which POINTS (if given) must equal.
  if (!have_width) {
    if (!have_points) return parse_error(in, "header has neither WIDTH nor POINTS");
    h->width = h->points;
    h->height = 1;
  }
  if (!checked_mul(h->width, h->height, &h->num_points)) {
    return parse_error(in, at_line(h->width_line) + "WIDTH x HEIGHT = " + std::to_string(h->width) +
                               " x " + std::to_string(h->height) + " overflows");
  }
  if (have_points && h->points != h->num_points) {
    return parse_error(in, at_line(h->points_line) + "POINTS " + std::to_string(h->points) +
                               " disagrees with WIDTH x HEIGHT = " + std::to_string(h->width) +
                               " x " + std::to_string(h->height) + " = " +
                               std::to_string(h->num_points));
  }
  return Status::Ok();
}

// Bytes per point of the fields, with or without the "_" padding fields; false on overflow.
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

// Values per point (sum of COUNT), with or without the padding fields; false on overflow.
bool point_values(const PcdHeader& h, bool include_padding, std::uint64_t* values) {
  std::uint64_t total = 0;
  for (const PcdField& f : h.fields) {
    if (f.is_padding() && !include_padding) continue;
    if (!checked_add(total, f.count, &total)) return false;
  }
  *values = total;
  return true;
}

// ------------------------------------------------------------------ ascii

Status read_ascii(const Input& in, const PcdHeader& h, PointSink* sink, PointCloud* cloud) {
  std::uint64_t values_all = 0, values_no_pad = 0;
  if (!point_values(h, true, &values_all) || !point_values(h, false, &values_no_pad)) {
    return parse_error(in, at_line(h.count_line) + "COUNT values overflow");
  }
  // Each value takes at least one character and one separator: bound POINTS by the text left
  // before reserving anything.
  const std::uint64_t remaining = in.size - h.body_offset + 1;
  std::uint64_t min_chars = 0;
  if (!checked_mul(values_no_pad, 2, &min_chars) || h.num_points > remaining / min_chars) {
    return parse_error(in, "ascii data too short: POINTS " + std::to_string(h.num_points) + " x " +
                               std::to_string(values_no_pad) + " values cannot fit in the " +
                               std::to_string(remaining - 1) + " bytes after the DATA line (line " +
                               std::to_string(h.data_line) + ")");
  }
  cloud->reserve(static_cast<std::size_t>(h.num_points));
  LineCursor cursor(in.data, in.size, h.body_offset, h.body_first_line);
  std::string_view line;
  // Whether the rows hold values for "_" padding fields is decided by the first row.
  bool padding_in_rows = true;
  std::uint64_t expected_values = values_all;
  for (std::uint64_t row = 0; row < h.num_points; ++row) {
    do {
      if (!cursor.next(&line)) {
        return parse_error(in, "ascii data truncated: POINTS is " + std::to_string(h.num_points) +
                                   ", the file ends after " + std::to_string(row) +
                                   " points (line " + std::to_string(cursor.line_number()) + ")");
      }
    } while (is_blank_line(line));
    const std::size_t ln = cursor.line_number();
    if (row == 0 && values_all != values_no_pad) {
      Tokenizer counter(line);
      std::string_view t;
      std::uint64_t found = 0;
      while (counter.next(&t)) ++found;
      if (found == values_no_pad) {
        padding_in_rows = false;
        expected_values = values_no_pad;
      }
    }
    Tokenizer tokens(line);
    std::string_view token;
    double xyz[3] = {0.0, 0.0, 0.0};
    std::uint64_t seen = 0;
    for (std::size_t f = 0; f < h.fields.size(); ++f) {
      const PcdField& field = h.fields[f];
      if (field.is_padding() && !padding_in_rows) continue;
      for (std::uint64_t k = 0; k < field.count; ++k, ++seen) {
        if (!tokens.next(&token)) {
          return parse_error(in, at_line(ln) + "expected " + std::to_string(expected_values) +
                                     " values per point, the line ends after " +
                                     std::to_string(seen) + " (in field '" + field.name + "')");
        }
        double value = 0.0;
        if (!parse_double(token, &value)) {
          return parse_error(in, at_line(ln) + "column " + std::to_string(tokens.column()) +
                                     ": field '" + field.name + "' should be a number, saw " +
                                     quoted(token));
        }
        if (k == 0) {
          for (int axis = 0; axis < 3; ++axis) {
            if (f == h.xyz_field[axis]) xyz[axis] = value;
          }
        }
      }
    }
    if (tokens.next(&token)) {
      return parse_error(in, at_line(ln) + "column " + std::to_string(tokens.column()) +
                                 ": unexpected extra value " + quoted(token) + " (expected " +
                                 std::to_string(expected_values) + " values per point)");
    }
    sink->add(xyz[0], xyz[1], xyz[2]);
  }
  while (cursor.next(&line)) {
    if (!is_blank_line(line)) {
      return parse_error(in, at_line(cursor.line_number()) +
                                 "unexpected data after the last of POINTS " +
                                 std::to_string(h.num_points) + " points: " + quoted(line));
    }
  }
  return Status::Ok();
}

// ------------------------------------------------------------------ binary (array of structures)

Status read_binary(const Input& in, const PcdHeader& h, PointSink* sink, PointCloud* cloud) {
  std::uint64_t bytes_per_point = 0, total = 0;
  if (!point_bytes(h, true, &bytes_per_point) ||
      !checked_mul(h.num_points, bytes_per_point, &total)) {
    return parse_error(
        in, "POINTS " + std::to_string(h.num_points) + " x point size overflows 64 bits");
  }
  const std::uint64_t remaining = in.size - h.body_offset;
  if (total > remaining) {
    return parse_error(
        in, "binary data truncated at byte " + std::to_string(in.size) + ": expected " +
                std::to_string(h.num_points) + " points x " + std::to_string(bytes_per_point) +
                " bytes = " + std::to_string(total) + " bytes after the header at byte " +
                std::to_string(h.body_offset) + ", file has " + std::to_string(remaining));
  }
  if (total < remaining) {
    return parse_error(in, "binary data of " + std::to_string(h.num_points) + " points x " +
                               std::to_string(bytes_per_point) + " bytes ends at byte " +
                               std::to_string(h.body_offset + total) + " but the file has " +
                               std::to_string(in.size) + " bytes (" +
                               std::to_string(remaining - total) + " unexpected extra bytes)");
  }
  std::size_t offset[3] = {0, 0, 0};
  ScalarLoader load[3];
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t index = h.xyz_field[axis];
    for (std::size_t f = 0; f < index; ++f) {
      offset[axis] += static_cast<std::size_t>(h.fields[f].size * h.fields[f].count);
    }
    load[axis] = scalar_loader(h.fields[index].scalar, ByteOrder::kLittleEndian);
  }
  cloud->reserve(static_cast<std::size_t>(h.num_points));
  const unsigned char* row = in.bytes() + h.body_offset;
  const std::size_t step = static_cast<std::size_t>(bytes_per_point);
  for (std::uint64_t i = 0; i < h.num_points; ++i, row += step) {
    sink->add(load[0](row + offset[0]), load[1](row + offset[1]), load[2](row + offset[2]));
  }
  return Status::Ok();
}

// ------------------------------------------------------------------ binary_compressed (LZF, SoA)

std::uint32_t load_u32_le(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

// LZF never expands more than 264 output bytes per 3 input bytes (its longest back reference):
// a larger claimed ratio cannot be genuine and is refused before allocating.
constexpr std::uint64_t kMaxLzfExpansion = 100;

Status read_binary_compressed(const Input& in, const PcdHeader& h, PointSink* sink,
                              PointCloud* cloud) {
  const std::uint64_t remaining = in.size - h.body_offset;
  if (remaining < 8) {
    return parse_error(in, "binary_compressed data truncated at byte " + std::to_string(in.size) +
                               ": expected an 8-byte size header (compressed, uncompressed) "
                               "after the DATA line at byte " +
                               std::to_string(h.body_offset) + ", file has " +
                               std::to_string(remaining));
  }
  const unsigned char* sizes = in.bytes() + h.body_offset;
  const std::uint32_t compressed = load_u32_le(sizes);
  const std::uint32_t uncompressed = load_u32_le(sizes + 4);
  if (compressed > remaining - 8) {
    return parse_error(in, "binary_compressed data truncated at byte " + std::to_string(in.size) +
                               ": the size header at byte " + std::to_string(h.body_offset) +
                               " announces " + std::to_string(compressed) +
                               " compressed bytes, file has " + std::to_string(remaining - 8));
  }
  if (compressed < remaining - 8) {
    return parse_error(in, "binary_compressed data ends at byte " +
                               std::to_string(h.body_offset + 8 + compressed) +
                               " but the file has " + std::to_string(in.size) + " bytes (" +
                               std::to_string(remaining - 8 - compressed) +
                               " unexpected extra bytes)");
  }
  std::uint64_t bytes_all = 0, bytes_no_pad = 0, total_all = 0, total_no_pad = 0;
  if (!point_bytes(h, true, &bytes_all) || !point_bytes(h, false, &bytes_no_pad) ||
      !checked_mul(h.num_points, bytes_all, &total_all) ||
      !checked_mul(h.num_points, bytes_no_pad, &total_no_pad)) {
    return parse_error(
        in, "POINTS " + std::to_string(h.num_points) + " x point size overflows 64 bits");
  }
  bool padding_in_data;
  if (uncompressed == total_no_pad) {
    padding_in_data = false;
  } else if (uncompressed == total_all) {
    padding_in_data = true;
  } else {
    return parse_error(
        in, "binary_compressed size header at byte " + std::to_string(h.body_offset) +
                " announces " + std::to_string(uncompressed) +
                " uncompressed bytes, but POINTS x point size = " + std::to_string(h.num_points) +
                " x " + std::to_string(bytes_no_pad) + " = " + std::to_string(total_no_pad) +
                " bytes");
  }
  if (h.num_points == 0) return Status::Ok();
  if (static_cast<std::uint64_t>(uncompressed) >
      static_cast<std::uint64_t>(compressed) * kMaxLzfExpansion) {
    return parse_error(
        in, "binary_compressed size header at byte " + std::to_string(h.body_offset) +
                " announces " + std::to_string(uncompressed) + " bytes from only " +
                std::to_string(compressed) + " compressed bytes, more than LZF can expand");
  }
  std::unique_ptr<unsigned char[]> buffer(new unsigned char[uncompressed]);
  const unsigned int got =
      lzf_decompress(sizes + 8, compressed, buffer.get(), static_cast<unsigned int>(uncompressed));
  if (got != uncompressed) {
    return parse_error(in, "binary_compressed LZF data from byte " +
                               std::to_string(h.body_offset + 8) + " is corrupt: decompressed " +
                               std::to_string(got) + " of the announced " +
                               std::to_string(uncompressed) + " bytes");
  }
  // Start of each axis's block in the structure-of-arrays layout, and the stride within it.
  std::size_t block[3] = {0, 0, 0};
  std::size_t stride[3] = {0, 0, 0};
  ScalarLoader load[3];
  const std::size_t n = static_cast<std::size_t>(h.num_points);
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t index = h.xyz_field[axis];
    for (std::size_t f = 0; f < index; ++f) {
      if (h.fields[f].is_padding() && !padding_in_data) continue;
      block[axis] += n * static_cast<std::size_t>(h.fields[f].size * h.fields[f].count);
    }
    stride[axis] = static_cast<std::size_t>(h.fields[index].size * h.fields[index].count);
    load[axis] = scalar_loader(h.fields[index].scalar, ByteOrder::kLittleEndian);
  }
  cloud->reserve(n);
  const unsigned char* base = buffer.get();
  for (std::size_t i = 0; i < n; ++i) {
    sink->add(load[0](base + block[0] + i * stride[0]), load[1](base + block[1] + i * stride[1]),
              load[2](base + block[2] + i * stride[2]));
  }
  return Status::Ok();
}

}  // namespace

Status read_pcd(const Input& in, PointCloud* cloud, ReadReport* report) {
  cloud->clear();
  report->format = Format::kPcd;
  PcdHeader header;
  Status status = parse_header(in, &header);
  if (!status.ok()) return status;
  report->encoding = data_name(header.data);
  PointSink sink(cloud);
  switch (header.data) {
    case PcdData::kAscii:
      status = read_ascii(in, header, &sink, cloud);
      break;
    case PcdData::kBinary:
      status = read_binary(in, header, &sink, cloud);
      break;
    case PcdData::kBinaryCompressed:
      status = read_binary_compressed(in, header, &sink, cloud);
      break;
  }
  if (!status.ok()) {
    cloud->clear();
    return status;
  }
  return finish_read(in, static_cast<std::size_t>(header.num_points), sink, *cloud, report);
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
