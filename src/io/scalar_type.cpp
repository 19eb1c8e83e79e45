// scalar_type.cpp - type names, sizes and byte-order-aware loads (see scalar_type.hpp).
#include "scalar_type.hpp"

#include <cstring>
#include <limits>

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

// The host is little endian on every platform ppcr targets; checked at compile time where the
// compiler tells (GCC, Clang).
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__)
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "ppcr_io assumes a little-endian host");
#endif

template <typename T>
struct Unsigned;
template <>
struct Unsigned<std::int8_t> {
  using type = std::uint8_t;
};
template <>
struct Unsigned<std::uint8_t> {
  using type = std::uint8_t;
};
template <>
struct Unsigned<std::int16_t> {
  using type = std::uint16_t;
};
template <>
struct Unsigned<std::uint16_t> {
  using type = std::uint16_t;
};
template <>
struct Unsigned<std::int32_t> {
  using type = std::uint32_t;
};
template <>
struct Unsigned<std::uint32_t> {
  using type = std::uint32_t;
};
template <>
struct Unsigned<std::int64_t> {
  using type = std::uint64_t;
};
template <>
struct Unsigned<std::uint64_t> {
  using type = std::uint64_t;
};
template <>
struct Unsigned<float> {
  using type = std::uint32_t;
};
template <>
struct Unsigned<double> {
  using type = std::uint64_t;
};

// Assembles the value's bits from bytes in the stored order, then reinterprets them (memcpy:
// no alignment or aliasing assumptions).
template <typename T, bool kBigEndian>
T load_raw(const unsigned char* p) {
  using U = typename Unsigned<T>::type;
  U bits;
  if (kBigEndian) {
    bits = 0;
    for (std::size_t i = 0; i < sizeof(U); ++i) bits = static_cast<U>((bits << 8) | p[i]);
  } else {
    std::memcpy(&bits, p, sizeof(U));
  }
  T value;
  std::memcpy(&value, &bits, sizeof(T));
  return value;
}

template <typename T, bool kBigEndian>
double load_as_double(const unsigned char* p) {
  return static_cast<double>(load_raw<T, kBigEndian>(p));
}

template <bool kBigEndian>
ScalarLoader loader_for_order(ScalarType type) {
  switch (type) {
    case ScalarType::kInt8:
      return &load_as_double<std::int8_t, kBigEndian>;
    case ScalarType::kUInt8:
      return &load_as_double<std::uint8_t, kBigEndian>;
    case ScalarType::kInt16:
      return &load_as_double<std::int16_t, kBigEndian>;
    case ScalarType::kUInt16:
      return &load_as_double<std::uint16_t, kBigEndian>;
    case ScalarType::kInt32:
      return &load_as_double<std::int32_t, kBigEndian>;
    case ScalarType::kUInt32:
      return &load_as_double<std::uint32_t, kBigEndian>;
    case ScalarType::kInt64:
      return &load_as_double<std::int64_t, kBigEndian>;
    case ScalarType::kUInt64:
      return &load_as_double<std::uint64_t, kBigEndian>;
    case ScalarType::kFloat32:
      return &load_as_double<float, kBigEndian>;
    case ScalarType::kFloat64:
      return &load_as_double<double, kBigEndian>;
  }
  return &load_as_double<double, kBigEndian>;
}

template <bool kBigEndian>
std::int64_t load_integer_for_order(ScalarType type, const unsigned char* p) {
  switch (type) {
    case ScalarType::kInt8:
      return load_raw<std::int8_t, kBigEndian>(p);
    case ScalarType::kUInt8:
      return load_raw<std::uint8_t, kBigEndian>(p);
    case ScalarType::kInt16:
      return load_raw<std::int16_t, kBigEndian>(p);
    case ScalarType::kUInt16:
      return load_raw<std::uint16_t, kBigEndian>(p);
    case ScalarType::kInt32:
      return load_raw<std::int32_t, kBigEndian>(p);
    case ScalarType::kUInt32:
      return load_raw<std::uint32_t, kBigEndian>(p);
    case ScalarType::kInt64:
      return load_raw<std::int64_t, kBigEndian>(p);
    case ScalarType::kUInt64: {
      const std::uint64_t v = load_raw<std::uint64_t, kBigEndian>(p);
      constexpr std::uint64_t kMax =
          static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
      return static_cast<std::int64_t>(v > kMax ? kMax : v);
    }
    case ScalarType::kFloat32:
    case ScalarType::kFloat64:
      break;
  }
  return -1;
}

}  // namespace

std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::kInt8:
    case ScalarType::kUInt8:
      return 1;
    case ScalarType::kInt16:
    case ScalarType::kUInt16:
      return 2;
    case ScalarType::kInt32:
    case ScalarType::kUInt32:
    case ScalarType::kFloat32:
      return 4;
    case ScalarType::kInt64:
    case ScalarType::kUInt64:
    case ScalarType::kFloat64:
      return 8;
  }
  return 8;
}

bool is_integer(ScalarType type) {
  return type != ScalarType::kFloat32 && type != ScalarType::kFloat64;
}

bool ply_scalar_type(std::string_view name, ScalarType* type) {
  struct Entry {
    const char* name;
    ScalarType type;
  };
  static const Entry kEntries[] = {
      {"char", ScalarType::kInt8},      {"int8", ScalarType::kInt8},
      {"uchar", ScalarType::kUInt8},    {"uint8", ScalarType::kUInt8},
      {"short", ScalarType::kInt16},    {"int16", ScalarType::kInt16},
      {"ushort", ScalarType::kUInt16},  {"uint16", ScalarType::kUInt16},
      {"int", ScalarType::kInt32},      {"int32", ScalarType::kInt32},
      {"uint", ScalarType::kUInt32},    {"uint32", ScalarType::kUInt32},
      {"float", ScalarType::kFloat32},  {"float32", ScalarType::kFloat32},
      {"double", ScalarType::kFloat64}, {"float64", ScalarType::kFloat64},
  };
  for (const Entry& e : kEntries) {
    if (name == e.name) {
      *type = e.type;
      return true;
    }
  }
  return false;
}

bool pcd_scalar_type(char letter, std::uint64_t size_bytes, ScalarType* type) {
  switch (letter) {
    case 'F':
      if (size_bytes == 4)
        *type = ScalarType::kFloat32;
      else if (size_bytes == 8)
        *type = ScalarType::kFloat64;
      else
        return false;
      return true;
    case 'I':
      if (size_bytes == 1)
        *type = ScalarType::kInt8;
      else if (size_bytes == 2)
        *type = ScalarType::kInt16;
      else if (size_bytes == 4)
        *type = ScalarType::kInt32;
      else if (size_bytes == 8)
        *type = ScalarType::kInt64;
      else
        return false;
      return true;
    case 'U':
      if (size_bytes == 1)
        *type = ScalarType::kUInt8;
      else if (size_bytes == 2)
        *type = ScalarType::kUInt16;
      else if (size_bytes == 4)
        *type = ScalarType::kUInt32;
      else if (size_bytes == 8)
        *type = ScalarType::kUInt64;
      else
        return false;
      return true;
    default:
      return false;
  }
}

ScalarLoader scalar_loader(ScalarType type, ByteOrder order) {
  return order == ByteOrder::kBigEndian ? loader_for_order<true>(type)
                                        : loader_for_order<false>(type);
}

std::int64_t load_integer(ScalarType type, ByteOrder order, const unsigned char* p) {
  return order == ByteOrder::kBigEndian ? load_integer_for_order<true>(type, p)
                                        : load_integer_for_order<false>(type, p);
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
