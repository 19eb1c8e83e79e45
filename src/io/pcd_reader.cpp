// pcd_reader.cpp - reads the x y z fields of a PCD file (v0.7, and v.5/v.6 headers), DATA ascii,
// binary or binary_compressed.
//
// The header is parsed in pcd_header.cpp. x, y, z are found by name and may have any TYPE/SIZE
// (F4 F8 I1..I8 U1..U8) and COUNT (the first value is used); all other fields, whatever their
// COUNT, are skipped. Organized clouds (HEIGHT > 1) are read row after row; their NaN padding
// points are dropped and counted like any non-finite point.
//
// A UTF-8 byte-order mark before the header is skipped. After the points, zero bytes (the padding
// PCL's command-line tools write) are accepted; other trailing bytes are refused.
//
// binary: POINTS records of the packed field layout (array of structures), little endian.
// binary_compressed: uint32 compressed size, uint32 uncompressed size (little endian), then LZF
// data that decompresses to the fields in structure-of-arrays order (all x, then all y, ...).
// As written by PCL, padding fields named "_" are absent from that data; data that include them
// (uncompressed size = POINTS x full point size) are accepted too. A build of ppcr_io without
// liblzf (PPCR_IO_HAVE_LZF unset: vendored where liblzf is missing) refuses such files, saying why.
#if defined(PPCR_IO_HAVE_LZF)
#include <lzf.h>
#endif

#include <memory>
#include <string>
#include <vector>

#include "formats.hpp"
#include "pcd_header.hpp"
#include "scalar_type.hpp"
#include "text_scan.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

std::string at_line(std::size_t line) { return "line " + std::to_string(line) + ": "; }

std::string quoted(std::string_view text) { return "'" + escape_for_message(text) + "'"; }

// Bytes after the points. PCL's blob writer (used by its command-line tools, e.g.
// pcl_convert_pcd_ascii_binary and pcl_ply2pcd) pads the data section with zeros up to a page
// boundary, so trailing zeros are padding; any other trailing byte means the header does not
// describe the data, and is refused with the count of extra bytes.
Status check_padding(const Input& in, std::size_t data_end, const std::string& what) {
  for (std::size_t i = data_end; i < in.size; ++i) {
    if (in.data[i] == '\0') continue;
    return parse_error(
        in, what + " ends at byte " + std::to_string(data_end) + " but the file has " +
                std::to_string(in.size) + " bytes (" + std::to_string(in.size - data_end) +
                " unexpected extra bytes, not zero padding: byte " + std::to_string(i) + " is " +
                quoted(std::string_view(in.data + i, 1)) + ")");
  }
  return Status::Ok();
}

// A line after the points that holds nothing: blanks, or the zero bytes of padding.
bool is_padding_line(std::string_view line) {
  for (char c : line) {
    if (c != '\0' && !is_blank_char(c)) return false;
  }
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
    if (!is_padding_line(line)) {
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
  Status padding = check_padding(in, static_cast<std::size_t>(h.body_offset + total),
                                 "binary data of " + std::to_string(h.num_points) + " points x " +
                                     std::to_string(bytes_per_point) + " bytes");
  if (!padding.ok()) return padding;
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

// LZF decompression where this build has liblzf; without it read_binary_compressed refuses the
// file before any call.
#if defined(PPCR_IO_HAVE_LZF)
constexpr bool kHaveLzf = true;
unsigned int decompress_lzf(const unsigned char* data, unsigned int size, unsigned char* out,
                            unsigned int out_size) {
  return lzf_decompress(data, size, out, out_size);
}
#else
constexpr bool kHaveLzf = false;
unsigned int decompress_lzf(const unsigned char*, unsigned int, unsigned char*, unsigned int) {
  return 0;
}
#endif

Status read_binary_compressed(const Input& in, const PcdHeader& h, PointSink* sink,
                              PointCloud* cloud) {
  if (!kHaveLzf) {
    return parse_error(in,
                       "DATA binary_compressed is LZF-compressed, and this build of ppcr_io "
                       "was made without liblzf (found missing at configure time): install "
                       "it (Debian: liblzf-dev) and rebuild ppcr, or save the cloud as "
                       "binary or ascii PCD");
  }
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
  Status padding = check_padding(
      in, h.body_offset + 8 + compressed,
      "binary_compressed data of " + std::to_string(compressed) + " compressed bytes");
  if (!padding.ok()) return padding;
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
      decompress_lzf(sizes + 8, compressed, buffer.get(), static_cast<unsigned int>(uncompressed));
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
  Status status = parse_pcd_header(in, &header);
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
