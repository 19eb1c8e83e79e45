// depth_png_util.hpp - depth PNGs written with libpng's own writer, and the pinhole
// back-projection written out, for the depth-image tests.
#pragma once

#include <png.h>

#include <catch2/catch.hpp>
#include <csetjmp>
#include <cstdio>
#include <string>
#include <vector>

#include "io_test_util.hpp"
#include "ppcr/io.hpp"

namespace depth_png_test {

using ppcr::PointCloud;
using ppcr::io::DepthCamera;

// Writes a width x height PNG of `bit_depth` bits and libpng colour type `color_type` whose
// samples are `samples` (row by row, channels interleaved). Returns false if libpng failed.
inline bool write_png(const std::string& path, int width, int height, int bit_depth, int color_type,
                      const std::vector<unsigned>& samples) {
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return false;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const int channels = color_type == PNG_COLOR_TYPE_RGB ? 3 : 1;
  const int bytes = bit_depth / 8;
  std::vector<unsigned char> row(static_cast<std::size_t>(width) * channels * bytes);
  for (int v = 0; v < height; ++v) {
    for (int i = 0; i < width * channels; ++i) {
      const unsigned s = samples[static_cast<std::size_t>(v) * width * channels + i];
      if (bytes == 2) {
        row[2 * i] = static_cast<unsigned char>(s >> 8);  // PNG: big endian
        row[2 * i + 1] = static_cast<unsigned char>(s & 0xff);
      } else {
        row[i] = static_cast<unsigned char>(s);
      }
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return std::fclose(file) == 0;
}

// The pinhole back-projection the reader documents, written out here.
inline Eigen::Vector3d back_project(double u, double v, unsigned d, const DepthCamera& c) {
  const double z = d / c.depth_scale;
  return Eigen::Vector3d((u - c.cx) * z / c.fx, (v - c.cy) * z / c.fy, z);
}

// A 7 x 5 depth image with holes (0), the extremes 1 and 65535, and bytes that differ in order.
inline std::vector<unsigned> test_depths() {
  std::vector<unsigned> d(35);
  for (unsigned i = 0; i < d.size(); ++i) d[i] = 1000 + 258 * i;  // 0x03E8 + 0x0102 i
  d[3] = 0;
  d[17] = 0;
  d[20] = 1;
  d[34] = 65535;
  return d;
}

// The expected cloud: the non-zero pixels in row order.
inline PointCloud expected_cloud(const std::vector<unsigned>& depths, int width,
                                 const DepthCamera& c) {
  PointCloud cloud;
  for (std::size_t i = 0; i < depths.size(); ++i) {
    if (depths[i] != 0) cloud.push_back(back_project(i % width, i / width, depths[i], c));
  }
  return cloud;
}

inline void check_close(const PointCloud& got, const PointCloud& want) {
  REQUIRE(got.size() == want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    INFO("point " << i);
    CHECK((got[i] - want[i]).norm() <= 1e-12 * (1.0 + want[i].norm()));
  }
}

}  // namespace depth_png_test
