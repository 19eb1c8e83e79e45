// ply_reader.cpp - reads the vertex positions of a PLY file (ascii, binary_little_endian,
// binary_big_endian).
//
// The header is parsed fully (format, elements, scalar and list properties, comment/obj_info,
// LF or CRLF line ends; a UTF-8 byte-order mark before "ply" is skipped). The body is walked
// element by element in header order, so elements before and after "vertex" (faces with list
// properties, ...) are skipped exactly; in the vertex element the properties x, y, z (any numeric
// type) are read as double and every other property, including list properties, is skipped. Every
// count is checked against the bytes left BEFORE anything is allocated, and the data must end
// exactly where the header says it does.
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

struct PlyProperty {
  std::string name;
  bool is_list = false;
  ScalarType type = ScalarType::kFloat32;      // the value type (the item type for lists)
  ScalarType count_type = ScalarType::kUInt8;  // lists only: the type of the length prefix
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t header_line = 0;  // line of the header declaring the element
};

enum class PlyEncoding { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;      // byte offset of the first byte after the end_header line
  std::size_t body_first_line = 0;  // line number of the first body line (ascii)
  std::size_t vertex_element = 0;   // index into elements
  std::size_t xyz_property[3] = {0, 0, 0};  // indices of x, y, z in the vertex element
};

const char* encoding_name(PlyEncoding e) {
  switch (e) {
    case PlyEncoding::kAscii:
      return "ascii";
    case PlyEncoding::kBinaryLittleEndian:
      return "binary_little_endian";
    case PlyEncoding::kBinaryBigEndian:
      return "binary_big_endian";
  }
  return "?";
}

std::string at_line(std::size_t line) { return "line " + std::to_string(line) + ": "; }

std::string quoted(std::string_view text) { return "'" + escape_for_message(text) + "'"; }

const char kKnownTypes[] =
    "char uchar short ushort int uint float double int8 uint8 int16 uint16 int32 uint32 float32 "
    "float64";

// Whether the header has shown its 'format' and 'end_header' lines yet.
struct HeaderProgress {
  bool have_format = false;
  bool have_end = false;
};

Status parse_end_header(const Input& in, std::size_t ln, Tokenizer* tokens,
                        HeaderProgress* progress) {
  std::string_view extra;
  if (tokens->next(&extra)) {
    return parse_error(in, at_line(ln) + "unexpected " + quoted(extra) + " after end_header");
  }
  progress->have_end = true;
  return Status::Ok();
}

Status parse_format_line(const Input& in, std::size_t ln, std::string_view line, Tokenizer* tokens,
                         HeaderProgress* progress, PlyHeader* header) {
  if (progress->have_format) return parse_error(in, at_line(ln) + "second 'format' line");
  std::string_view t1, t2, extra;
  if (!tokens->next(&t1) || !tokens->next(&t2) || tokens->next(&extra)) {
    return parse_error(in, at_line(ln) + "expected 'format <encoding> 1.0', saw " + quoted(line));
  }
  if (t1 == "ascii") {
    header->encoding = PlyEncoding::kAscii;
  } else if (t1 == "binary_little_endian") {
    header->encoding = PlyEncoding::kBinaryLittleEndian;
  } else if (t1 == "binary_big_endian") {
    header->encoding = PlyEncoding::kBinaryBigEndian;
  } else {
    return parse_error(in, at_line(ln) + "unknown PLY format " + quoted(t1) +
                               " (expected ascii, binary_little_endian or binary_big_endian)");
  }
  if (t2 != "1.0" && t2 != "1") {
    return parse_error(in,
                       at_line(ln) + "unsupported PLY version " + quoted(t2) + " (expected 1.0)");
  }
  progress->have_format = true;
  return Status::Ok();
}

Status parse_element_line(const Input& in, std::size_t ln, std::string_view line, Tokenizer* tokens,
                          PlyHeader* header) {
  std::string_view t1, t2, extra;
  if (!tokens->next(&t1) || !tokens->next(&t2) || tokens->next(&extra)) {
    return parse_error(in, at_line(ln) + "expected 'element <name> <count>', saw " + quoted(line));
  }
  PlyElement element;
  element.name = std::string(t1);
  element.header_line = ln;
  if (!parse_uint64(t2, &element.count)) {
    const bool negative = !t2.empty() && t2[0] == '-';
    return parse_error(
        in, at_line(ln) + "element " + quoted(t1) + " count " + quoted(t2) +
                (negative ? " is negative" : " is not a non-negative integer below 2^64"));
  }
  header->elements.push_back(std::move(element));
  return Status::Ok();
}

// The rest of a 'property list <count type> <item type> <name>' line (after "list").
Status parse_list_property(const Input& in, std::size_t ln, std::string_view line,
                           Tokenizer* tokens, PlyProperty* property) {
  std::string_view t2, t3, t4, extra;
  if (!tokens->next(&t2) || !tokens->next(&t3) || !tokens->next(&t4) || tokens->next(&extra)) {
    return parse_error(in, at_line(ln) +
                               "expected 'property list <count type> <item type> <name>', "
                               "saw " +
                               quoted(line));
  }
  property->is_list = true;
  if (!ply_scalar_type(t2, &property->count_type)) {
    return parse_error(in, at_line(ln) + "unknown list count type " + quoted(t2) +
                               " (known: " + kKnownTypes + ")");
  }
  if (!is_integer(property->count_type)) {
    return parse_error(in,
                       at_line(ln) + "list count type " + quoted(t2) + " is not an integer type");
  }
  if (!ply_scalar_type(t3, &property->type)) {
    return parse_error(
        in, at_line(ln) + "unknown list item type " + quoted(t3) + " (known: " + kKnownTypes + ")");
  }
  property->name = std::string(t4);
  return Status::Ok();
}

// The rest of a 'property <type> <name>' line, whose type token has been read.
Status parse_scalar_property(const Input& in, std::size_t ln, std::string_view line,
                             std::string_view type, Tokenizer* tokens, PlyProperty* property) {
  std::string_view name, extra;
  if (!tokens->next(&name) || tokens->next(&extra)) {
    return parse_error(in, at_line(ln) + "expected 'property <type> <name>', saw " + quoted(line));
  }
  if (!ply_scalar_type(type, &property->type)) {
    return parse_error(in, at_line(ln) + "unknown property type " + quoted(type) +
                               " (known: " + kKnownTypes + ")");
  }
  property->name = std::string(name);
  return Status::Ok();
}

// A property line adds a property to the element declared last.
Status parse_property_line(const Input& in, std::size_t ln, std::string_view line,
                           Tokenizer* tokens, PlyHeader* header) {
  if (header->elements.empty()) {
    return parse_error(in, at_line(ln) + "'property' before any 'element'");
  }
  PlyProperty property;
  std::string_view t1;
  if (!tokens->next(&t1)) {
    return parse_error(in, at_line(ln) + "expected 'property <type> <name>', saw " + quoted(line));
  }
  Status s = t1 == "list" ? parse_list_property(in, ln, line, tokens, &property)
                          : parse_scalar_property(in, ln, line, t1, tokens, &property);
  if (!s.ok()) return s;
  header->elements.back().properties.push_back(std::move(property));
  return Status::Ok();
}

// One header line after "ply", dispatched on its keyword; blank, comment and obj_info lines are
// skipped.
Status parse_header_line(const Input& in, std::size_t ln, std::string_view line,
                         HeaderProgress* progress, PlyHeader* header) {
  Tokenizer tokens(line);
  std::string_view keyword;
  if (!tokens.next(&keyword)) return Status::Ok();  // blank header line
  if (keyword == "comment" || keyword == "obj_info") return Status::Ok();
  if (keyword == "end_header") return parse_end_header(in, ln, &tokens, progress);
  if (keyword == "format") return parse_format_line(in, ln, line, &tokens, progress, header);
  if (keyword == "element") return parse_element_line(in, ln, line, &tokens, header);
  if (keyword == "property") return parse_property_line(in, ln, line, &tokens, header);
  return parse_error(in, at_line(ln) + "unknown header keyword " + quoted(keyword) +
                             " (expected format, element, property, comment, obj_info or "
                             "end_header)");
}

// Reads the header lines from "ply" (a UTF-8 byte-order mark before it is skipped) to
// end_header and sets where the body starts.
Status read_header_lines(const Input& in, PlyHeader* header) {
  LineCursor cursor(in.data, in.size, utf8_bom_size(in.data, in.size));
  std::string_view line;
  if (!cursor.next(&line) || line != "ply") {
    return parse_error(in, "not a PLY file: line 1 should be 'ply', saw " +
                               quoted(std::string_view(in.data, in.size < 16 ? in.size : 16)));
  }
  HeaderProgress progress;
  while (!progress.have_end && cursor.next(&line)) {
    Status s = parse_header_line(in, cursor.line_number(), line, &progress, header);
    if (!s.ok()) return s;
  }
  if (!progress.have_end) {
    return parse_error(in, "header has no 'end_header' line (the file ends at byte " +
                               std::to_string(in.size) + ", line " +
                               std::to_string(cursor.line_number()) + ")");
  }
  if (!progress.have_format) return parse_error(in, "header has no 'format' line");
  header->body_offset = cursor.offset();
  header->body_first_line = cursor.line_number() + 1;
  return Status::Ok();
}

// Finds the element 'vertex': exactly once.
Status find_vertex_element(const Input& in, PlyHeader* header) {
  bool found_vertex = false;
  for (std::size_t e = 0; e < header->elements.size(); ++e) {
    if (header->elements[e].name != "vertex") continue;
    if (found_vertex) {
      return parse_error(in, at_line(header->elements[e].header_line) + "second 'vertex' element");
    }
    found_vertex = true;
    header->vertex_element = e;
  }
  if (!found_vertex) return parse_error(in, "header declares no 'vertex' element");
  return Status::Ok();
}

// Finds the vertex properties x, y and z: each exactly once, and scalar.
Status find_xyz_properties(const Input& in, PlyHeader* header) {
  const PlyElement& vertex = header->elements[header->vertex_element];
  static const char* const kAxes[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    bool found = false;
    for (std::size_t p = 0; p < vertex.properties.size(); ++p) {
      if (vertex.properties[p].name != kAxes[axis]) continue;
      if (found) {
        return parse_error(in, "element 'vertex' (line " + std::to_string(vertex.header_line) +
                                   ") has property '" + kAxes[axis] + "' twice");
      }
      if (vertex.properties[p].is_list) {
        return parse_error(in, "element 'vertex' (line " + std::to_string(vertex.header_line) +
                                   "): property '" + kAxes[axis] +
                                   "' is a list, expected a scalar");
      }
      found = true;
      header->xyz_property[axis] = p;
    }
    if (!found) {
      return parse_error(in, "element 'vertex' (line " + std::to_string(vertex.header_line) +
                                 ") has no property '" + kAxes[axis] + "'");
    }
  }
  return Status::Ok();
}

Status parse_header(const Input& in, PlyHeader* header) {
  Status s = read_header_lines(in, header);
  if (s.ok()) s = find_vertex_element(in, header);
  if (s.ok()) s = find_xyz_properties(in, header);
  return s;
}

// ------------------------------------------------------------------ binary body

std::string rows_times_bytes(std::uint64_t rows, std::uint64_t bytes_per_row) {
  std::string s = std::to_string(rows) + " rows x " + std::to_string(bytes_per_row) + " bytes";
  std::uint64_t total = 0;
  if (checked_mul(rows, bytes_per_row, &total)) s += " = " + std::to_string(total) + " bytes";
  return s;
}

class BinaryBody {
 public:
  BinaryBody(const Input& in, const PlyHeader& header)
      : in_(in),
        header_(header),
        order_(header.encoding == PlyEncoding::kBinaryBigEndian ? ByteOrder::kBigEndian
                                                                : ByteOrder::kLittleEndian) {}

  Status read(PointSink* sink, PointCloud* cloud) {
    pos_ = header_.body_offset;
    for (std::size_t e = 0; e < header_.elements.size(); ++e) {
      const PlyElement& element = header_.elements[e];
      bool fixed = true;
      std::uint64_t min_row_bytes = 0;  // fixed part + list length prefixes
      for (const PlyProperty& p : element.properties) {
        if (p.is_list) {
          fixed = false;
          min_row_bytes += scalar_size(p.count_type);
        } else {
          min_row_bytes += scalar_size(p.type);
        }
      }
      const bool is_vertex = e == header_.vertex_element;
      const std::uint64_t remaining = in_.size - pos_;
      if (min_row_bytes > 0 && element.count > remaining / min_row_bytes) {
        return parse_error(in_, "binary data of element '" + element.name + "' truncated at byte " +
                                    std::to_string(in_.size) + ": expected " +
                                    rows_times_bytes(element.count, min_row_bytes) +
                                    (fixed ? "" : " (at least)") + " from byte " +
                                    std::to_string(pos_) + (e == 0 ? " (end of header)" : "") +
                                    ", file has " + std::to_string(remaining) + " bytes left");
      }
      if (is_vertex) cloud->reserve(static_cast<std::size_t>(element.count));
      Status status = fixed ? read_fixed_rows(element, min_row_bytes, is_vertex, sink)
                            : read_variable_rows(element, is_vertex, sink);
      if (!status.ok()) return status;
    }
    if (pos_ != in_.size) {
      return parse_error(in_, "the header's elements end at byte " + std::to_string(pos_) +
                                  " but the file has " + std::to_string(in_.size) + " bytes (" +
                                  std::to_string(in_.size - pos_) +
                                  " unexpected bytes after the last element)");
    }
    return Status::Ok();
  }

 private:
  Status read_fixed_rows(const PlyElement& element, std::uint64_t row_bytes, bool is_vertex,
                         PointSink* sink) {
    // The caller checked count * row_bytes <= bytes left.
    if (is_vertex) {
      std::size_t offset[3] = {0, 0, 0};
      ScalarLoader load[3];
      for (int axis = 0; axis < 3; ++axis) {
        const std::size_t index = header_.xyz_property[axis];
        for (std::size_t p = 0; p < index; ++p)
          offset[axis] += scalar_size(element.properties[p].type);
        load[axis] = scalar_loader(element.properties[index].type, order_);
      }
      const unsigned char* row = in_.bytes() + pos_;
      const std::size_t step = static_cast<std::size_t>(row_bytes);
      for (std::uint64_t i = 0; i < element.count; ++i, row += step) {
        sink->add(load[0](row + offset[0]), load[1](row + offset[1]), load[2](row + offset[2]));
      }
    }
    pos_ += static_cast<std::size_t>(element.count * row_bytes);
    return Status::Ok();
  }

  Status truncated_row(const PlyElement& element, std::uint64_t row, const PlyProperty& p,
                       std::uint64_t needed) const {
    return parse_error(in_, "binary data of element '" + element.name + "' truncated at byte " +
                                std::to_string(in_.size) + ": row " + std::to_string(row) +
                                ", property '" + p.name + "' at byte " + std::to_string(pos_) +
                                " needs " + std::to_string(needed) + " bytes, file has " +
                                std::to_string(in_.size - pos_) + " left");
  }

  Status read_variable_rows(const PlyElement& element, bool is_vertex, PointSink* sink) {
    const std::size_t ix = header_.xyz_property[0];
    const std::size_t iy = header_.xyz_property[1];
    const std::size_t iz = header_.xyz_property[2];
    for (std::uint64_t row = 0; row < element.count; ++row) {
      double xyz[3] = {0.0, 0.0, 0.0};
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.is_list) {
          const std::size_t size = scalar_size(property.type);
          if (in_.size - pos_ < size) return truncated_row(element, row, property, size);
          if (is_vertex) {
            const unsigned char* at = in_.bytes() + pos_;
            if (p == ix) xyz[0] = scalar_loader(property.type, order_)(at);
            if (p == iy) xyz[1] = scalar_loader(property.type, order_)(at);
            if (p == iz) xyz[2] = scalar_loader(property.type, order_)(at);
          }
          pos_ += size;
          continue;
        }
        const std::size_t count_size = scalar_size(property.count_type);
        if (in_.size - pos_ < count_size) return truncated_row(element, row, property, count_size);
        const std::int64_t length = load_integer(property.count_type, order_, in_.bytes() + pos_);
        if (length < 0) {
          return parse_error(in_, "element '" + element.name + "' row " + std::to_string(row) +
                                      ": list '" + property.name + "' at byte " +
                                      std::to_string(pos_) + " has negative length " +
                                      std::to_string(length));
        }
        pos_ += count_size;
        const std::uint64_t item_size = scalar_size(property.type);
        const std::uint64_t items = static_cast<std::uint64_t>(length);
        if (items > (in_.size - pos_) / item_size) {
          return parse_error(
              in_, "binary data of element '" + element.name + "' truncated at byte " +
                       std::to_string(in_.size) + ": row " + std::to_string(row) + ", list '" +
                       property.name + "' at byte " + std::to_string(pos_) + " needs " +
                       std::to_string(items) + " items x " + std::to_string(item_size) +
                       " bytes, file has " + std::to_string(in_.size - pos_) + " bytes left");
        }
        pos_ += static_cast<std::size_t>(items * item_size);
      }
      if (is_vertex) sink->add(xyz[0], xyz[1], xyz[2]);
    }
    return Status::Ok();
  }

  const Input& in_;
  const PlyHeader& header_;
  ByteOrder order_;
  std::size_t pos_ = 0;
};

// ------------------------------------------------------------------ ascii body

class AsciiBody {
 public:
  AsciiBody(const Input& in, const PlyHeader& header)
      : in_(in),
        header_(header),
        cursor_(in.data, in.size, header.body_offset, header.body_first_line) {}

  Status read(PointSink* sink, PointCloud* cloud) {
    for (std::size_t e = 0; e < header_.elements.size(); ++e) {
      const PlyElement& element = header_.elements[e];
      if (element.properties.empty()) continue;  // rows of nothing: no text to read
      // Each row holds at least one character per property plus a separator: a count the
      // remaining text cannot hold is rejected before anything is reserved.
      const std::uint64_t min_row_chars = 2 * element.properties.size();
      const std::uint64_t remaining = in_.size - cursor_.offset() + 1;
      if (element.count > remaining / min_row_chars) {
        return parse_error(in_, "ascii data too short: element '" + element.name + "' (line " +
                                    std::to_string(element.header_line) + ") declares " +
                                    std::to_string(element.count) + " rows of " +
                                    std::to_string(element.properties.size()) +
                                    " values, but only " + std::to_string(remaining - 1) +
                                    " bytes follow byte " + std::to_string(cursor_.offset()));
      }
      const bool is_vertex = e == header_.vertex_element;
      if (is_vertex) cloud->reserve(static_cast<std::size_t>(element.count));
      for (std::uint64_t row = 0; row < element.count; ++row) {
        Status status = read_row(element, row, is_vertex, sink);
        if (!status.ok()) return status;
      }
    }
    std::string_view line;
    while (cursor_.next(&line)) {
      if (!is_blank_line(line)) {
        return parse_error(in_, at_line(cursor_.line_number()) +
                                    "unexpected data after the last element: " + quoted(line));
      }
    }
    return Status::Ok();
  }

 private:
  Status read_row(const PlyElement& element, std::uint64_t row, bool is_vertex, PointSink* sink) {
    std::string_view line;
    do {
      if (!cursor_.next(&line)) {
        return parse_error(in_, "ascii data truncated: element '" + element.name + "' (line " +
                                    std::to_string(element.header_line) + ") declares " +
                                    std::to_string(element.count) + " rows, the file ends after " +
                                    std::to_string(row) + " of them (line " +
                                    std::to_string(cursor_.line_number()) + ")");
      }
    } while (is_blank_line(line));
    const std::size_t ln = cursor_.line_number();
    Tokenizer tokens(line);
    std::string_view token;
    double xyz[3] = {0.0, 0.0, 0.0};
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      if (!tokens.next(&token)) {
        return parse_error(
            in_, at_line(ln) + "element '" + element.name + "' row " + std::to_string(row) +
                     ": line ends before property '" + property.name + "' (" + std::to_string(p) +
                     " of " + std::to_string(element.properties.size()) + " properties seen)");
      }
      if (property.is_list) {
        std::uint64_t length = 0;
        if (!parse_uint64(token, &length)) {
          return parse_error(in_, at_line(ln) + "column " + std::to_string(tokens.column()) +
                                      ": list length of '" + property.name +
                                      "' should be a non-negative integer, saw " + quoted(token));
        }
        for (std::uint64_t k = 0; k < length; ++k) {
          double ignored = 0.0;
          if (!tokens.next(&token)) {
            return parse_error(in_, at_line(ln) + "list '" + property.name + "' declares " +
                                        std::to_string(length) + " items, the line holds " +
                                        std::to_string(k));
          }
          if (!parse_double(token, &ignored)) {
            return parse_error(in_, at_line(ln) + "column " + std::to_string(tokens.column()) +
                                        ": item of list '" + property.name +
                                        "' should be a number, saw " + quoted(token));
          }
        }
        continue;
      }
      double value = 0.0;
      if (!parse_double(token, &value)) {
        return parse_error(in_, at_line(ln) + "column " + std::to_string(tokens.column()) +
                                    ": property '" + property.name + "' of element '" +
                                    element.name + "' should be a number, saw " + quoted(token));
      }
      if (is_vertex) {
        for (int axis = 0; axis < 3; ++axis) {
          if (p == header_.xyz_property[axis]) xyz[axis] = value;
        }
      }
    }
    if (tokens.next(&token)) {
      return parse_error(in_, at_line(ln) + "column " + std::to_string(tokens.column()) +
                                  ": unexpected extra value " + quoted(token) + " (element '" +
                                  element.name + "' has " +
                                  std::to_string(element.properties.size()) + " properties)");
    }
    if (is_vertex) sink->add(xyz[0], xyz[1], xyz[2]);
    return Status::Ok();
  }

  const Input& in_;
  const PlyHeader& header_;
  LineCursor cursor_;
};

}  // namespace

Status read_ply(const Input& in, PointCloud* cloud, ReadReport* report) {
  cloud->clear();
  report->format = Format::kPly;
  PlyHeader header;
  Status status = parse_header(in, &header);
  if (!status.ok()) return status;
  report->encoding = encoding_name(header.encoding);
  PointSink sink(cloud);
  if (header.encoding == PlyEncoding::kAscii) {
    status = AsciiBody(in, header).read(&sink, cloud);
  } else {
    status = BinaryBody(in, header).read(&sink, cloud);
  }
  if (!status.ok()) {
    cloud->clear();
    return status;
  }
  return finish_read(in, static_cast<std::size_t>(header.elements[header.vertex_element].count),
                     sink, *cloud, report);
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
