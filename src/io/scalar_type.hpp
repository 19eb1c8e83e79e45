// scalar_type.hpp - the binary numeric types of PLY and PCD, and loading them as double
// (private to ppcr_io).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "ppcr/abi.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

enum class ScalarType {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kInt64,
  kUInt64,
  kFloat32,
  kFloat64
};

enum class ByteOrder { kLittleEndian, kBigEndian };

/// Size of one value in bytes (1, 2, 4 or 8).
std::size_t scalar_size(ScalarType type);

bool is_integer(ScalarType type);

/// PLY type names: char uchar short ushort int uint float double and int8 uint8 int16 uint16
/// int32 uint32 float32 float64. False for anything else (PLY has no 64-bit integers).
bool ply_scalar_type(std::string_view name, ScalarType* type);

/// PCD TYPE letter (F, I, U) with SIZE in bytes: F4 F8, I1 I2 I4 I8, U1 U2 U4 U8.
bool pcd_scalar_type(char letter, std::uint64_t size_bytes, ScalarType* type);

/// Reads one value stored at p (any alignment) and converts it to double.
using ScalarLoader = double (*)(const unsigned char* p);

/// The loader for a type stored in the given byte order.
ScalarLoader scalar_loader(ScalarType type, ByteOrder order);

/// Reads an integer-typed value (a PLY list length). Signed types may give negative values;
/// 64-bit unsigned values above INT64_MAX are clamped to INT64_MAX. Only for is_integer(type).
std::int64_t load_integer(ScalarType type, ByteOrder order, const unsigned char* p);

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
