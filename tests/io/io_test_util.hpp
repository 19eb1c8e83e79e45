// io_test_util.hpp - helpers for the ppcr_io tests: building files byte by byte (independently of
// the library's own encoders), temporary folders, and bit-exact comparisons.
#pragma once

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "ppcr/types.hpp"

namespace io_test {

/// Appends the bytes of a value in little- or big-endian order, built with shifts (not memcpy of
/// a host value), so the tests do not share the library's byte-order code.
template <typename T>
void put(std::string* out, T value, bool big_endian = false) {
  static_assert(sizeof(T) <= 8, "scalar");
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    const std::size_t shift = 8 * (big_endian ? sizeof(T) - 1 - i : i);
    out->push_back(static_cast<char>((bits >> shift) & 0xffu));
  }
}

inline void put_le_u32(std::string* out, std::uint32_t v) { put<std::uint32_t>(out, v, false); }

/// A fresh empty folder under the system temp dir, removed when the object dies.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("ppcr_io_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

/// True if both clouds have the same size and every coordinate has the same bit pattern.
inline bool bit_identical(const ppcr::PointCloud& a, const ppcr::PointCloud& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(a[i].data(), b[i].data(), 3 * sizeof(double)) != 0) return false;
  }
  return true;
}

/// A cloud of awkward doubles: random values over many magnitudes, plus -0, the smallest
/// subnormal, the largest finite double, and values that need all 17 digits.
inline ppcr::PointCloud awkward_cloud(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  ppcr::PointCloud cloud;
  cloud.emplace_back(-0.0, 0.0, 0.1);
  cloud.emplace_back(std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max(),
                     -std::numeric_limits<double>::max());
  cloud.emplace_back(1.0 / 3.0, 2.0 / 3.0, 123456789.123456789);
  cloud.emplace_back(std::numeric_limits<double>::min(), -1e-310, 9007199254740993.0);
  while (cloud.size() < n) {
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) p[k] = std::ldexp(mantissa(rng), exponent(rng) / 10 * 3);
    cloud.push_back(p);
  }
  return cloud;
}

/// A street-like LiDAR frame: ground, two walls and a pole (14,000 points, metres).
inline ppcr::PointCloud street_frame() {
  ppcr::PointCloud frame;
  for (double x = -20; x <= 20; x += 0.25) {
    for (double y = -8; y <= 8; y += 0.25) frame.emplace_back(x, y, -1.7 + 0.01 * std::sin(x));
    for (double z = -1.7; z <= 2; z += 0.25) {
      frame.emplace_back(x, 8.0 + 0.3 * std::sin(0.5 * x), z);
      frame.emplace_back(x, -8.0, z + 0.05 * x);
    }
  }
  for (double z = -1.7; z <= 3; z += 0.1) frame.emplace_back(5.0, 2.0, z);
  return frame;
}

}  // namespace io_test
