// pcd_header.hpp - the header of a PCD file: its fields, point count and data encoding
// (private to ppcr_io; the data sections are read in pcd_reader.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "reader_common.hpp"
#include "scalar_type.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

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

const char* data_name(PcdData d);

/// Parses the header: '#' comment lines, VERSION, FIELDS (or COLUMNS), SIZE, TYPE (default F),
/// COUNT (default 1), WIDTH, HEIGHT (default 1), VIEWPOINT (optional, 7 numbers), POINTS (default
/// WIDTH*HEIGHT, else must equal it), DATA (last). A UTF-8 byte-order mark before it is skipped.
/// Finds x, y, z (each exactly once) and checks every count for overflow.
Status parse_pcd_header(const Input& in, PcdHeader* h);

/// Bytes per point of the fields, with or without the "_" padding fields; false on overflow.
bool point_bytes(const PcdHeader& h, bool include_padding, std::uint64_t* bytes);

/// Values per point (sum of COUNT), with or without the padding fields; false on overflow.
bool point_values(const PcdHeader& h, bool include_padding, std::uint64_t* values);

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
