// depth_png.cpp - depth images (16-bit grayscale PNG, as Kinect-type cameras and the TUM RGB-D,
// ICL-NUIM and Redwood datasets store them), decoded by libpng and back-projected through a
// pinhole camera: pixel (u, v) with stored value d > 0 is the point
// ((u - cx) z / fx, (v - cy) z / fy, z) with z = d / depth_scale; d = 0 means "no reading".
//
// libpng reports errors by longjmp. The decoder is arranged so that a longjmp skips only
// libpng's own frames: the one function that calls setjmp holds nothing but trivially
// destructible locals and a guard that frees libpng's structures on every way out, and the
// points go to the caller's cloud. Rows are decoded one at a time, so memory follows the data
// actually decompressed, not the size a (possibly hostile) header claims.
#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "formats.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

// What libpng's callbacks share: the bytes still to read and the first error message.
struct PngSource {
  const unsigned char* data;
  std::size_t size;
  std::size_t offset;
  char message[200];
};

void read_bytes(png_structp png, png_bytep out, png_size_t count) {
  auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
  if (count > source->size - source->offset) png_error(png, "the file ends inside the image");
  std::memcpy(out, source->data + source->offset, count);
  source->offset += count;
}

[[noreturn]] void on_error(png_structp png, png_const_charp message) {
  auto* source = static_cast<PngSource*>(png_get_error_ptr(png));
  std::snprintf(source->message, sizeof source->message, "%s", message);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // the library never prints

// Frees libpng's structures however the decoder leaves (return, longjmp back into it, or an
// exception from the cloud's allocation).
struct PngGuard {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngGuard() { png_destroy_read_struct(&png, info != nullptr ? &info : nullptr, nullptr); }
};

// Checks the header's image type; empty if it is a depth image we read.
std::string unsupported_type(int bit_depth, int color_type, int interlace) {
  if (color_type != PNG_COLOR_TYPE_GRAY || bit_depth != 16) {
    const char* colour = color_type == PNG_COLOR_TYPE_GRAY         ? "grayscale"
                         : color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? "grayscale with alpha"
                         : color_type == PNG_COLOR_TYPE_PALETTE    ? "palette"
                         : color_type == PNG_COLOR_TYPE_RGB        ? "RGB"
                                                                   : "RGBA";
    const bool grayscale =
        color_type == PNG_COLOR_TYPE_GRAY || color_type == PNG_COLOR_TYPE_GRAY_ALPHA;
    return "a depth image must be a 16-bit grayscale PNG; this one is " +
           std::to_string(bit_depth) + "-bit " + colour + (grayscale ? "" : " (a colour image?)");
  }
  if (interlace != PNG_INTERLACE_NONE) return "interlaced (Adam7) depth images are not read";
  return std::string();
}

// The most pixels read (32 Mpx, four times a 4K depth map): deflate packs a constant row about
// 1000:1, so without a bound a file of a few MB could ask for billions of points.
constexpr std::uint64_t kMaxPixels = std::uint64_t{1} << 25;

// Decodes `source` row by row into `sink`. Returns false with source->message set on a libpng
// error, or with *type_error set for an image that is not a depth image we read.
bool decode(PngSource* source, const DepthCamera& camera, PointSink* sink,
            std::vector<unsigned char>* row, std::string* type_error, std::uint64_t* pixels) {
  PngGuard guard;
  guard.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, source, on_error, on_warning);
  if (guard.png == nullptr) {
    std::snprintf(source->message, sizeof source->message,
                  "libpng could not start (out of memory, or another libpng version)");
    return false;
  }
  guard.info = png_create_info_struct(guard.png);
  if (guard.info == nullptr) {
    std::snprintf(source->message, sizeof source->message, "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(guard.png))) return false;  // on_error wrote the message
  png_set_read_fn(guard.png, source, read_bytes);
  png_read_info(guard.png, guard.info);
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0, interlace = 0;
  png_get_IHDR(guard.png, guard.info, &width, &height, &bit_depth, &color_type, &interlace, nullptr,
               nullptr);
  *type_error = unsupported_type(bit_depth, color_type, interlace);
  *pixels = std::uint64_t{width} * height;
  if (type_error->empty() && *pixels > kMaxPixels) {
    *type_error = std::to_string(width) + " x " + std::to_string(height) +
                  " pixels: more than the 2^25 a depth image may have";
  }
  if (!type_error->empty()) return false;
  row->resize(png_get_rowbytes(guard.png, guard.info));
  for (png_uint_32 v = 0; v < height; ++v) {
    png_read_row(guard.png, row->data(), nullptr);
    const double y_per_z = (v - camera.cy) / camera.fy;
    for (png_uint_32 u = 0; u < width; ++u) {
      // PNG stores 16-bit samples big endian, whatever the host.
      const unsigned d = (unsigned{(*row)[2 * u]} << 8) | (*row)[2 * u + 1];
      if (d == 0) continue;
      const double z = d / camera.depth_scale;
      sink->add((u - camera.cx) / camera.fx * z, y_per_z * z, z);
    }
  }
  png_read_end(guard.png, nullptr);  // checks the remaining chunks' CRCs
  return true;
}

bool is_png_signature(const char* data, std::size_t size) {
  return size >= 8 && png_sig_cmp(reinterpret_cast<png_const_bytep>(data), 0, 8) == 0;
}

}  // namespace

Status check_depth_camera(const std::string& name, const DepthCamera& camera) {
  const struct {
    const char* field;
    double value;
    bool positive;
  } fields[] = {{"fx", camera.fx, true},
                {"fy", camera.fy, true},
                {"cx", camera.cx, false},
                {"cy", camera.cy, false},
                {"depth_scale", camera.depth_scale, true}};
  for (const auto& f : fields) {
    if (!std::isfinite(f.value) || (f.positive && !(f.value > 0.0))) {
      char value[32];
      std::snprintf(value, sizeof value, "%.17g", f.value);
      return Status(StatusCode::kInvalidArgument,
                    name + ": depth camera " + f.field + " = " + value +
                        (f.positive ? " (must be finite and > 0)" : " (must be finite)"));
    }
  }
  return Status::Ok();
}

Status read_depth_png(const Input& in, const DepthCamera& camera, PointCloud* cloud,
                      ReadReport* report) {
  cloud->clear();
  report->format = Format::kDepthPng;
  report->encoding = "png_gray16";
  Status status = check_depth_camera(in.name, camera);
  if (!status.ok()) return status;
  if (!is_png_signature(in.data, in.size)) {
    return parse_error(in, "not a PNG file (its first 8 bytes are not the PNG signature)");
  }
  PngSource source{in.bytes(), in.size, 0, {}};
  std::vector<unsigned char> row;
  std::string type_error;
  std::uint64_t pixels = 0;
  PointSink sink(cloud);  // a camera of extreme values can make a point infinite: dropped
  if (!decode(&source, camera, &sink, &row, &type_error, &pixels)) {
    cloud->clear();
    return parse_error(in, type_error.empty() ? std::string("PNG: ") + source.message : type_error);
  }
  if (cloud->empty() && sink.non_finite() == 0) {
    return Status(StatusCode::kEmptyCloud, in.name + ": the depth image's " +
                                               std::to_string(pixels) +
                                               " pixels all read 0 (no depth)");
  }
  // Points: the pixels with depth; infinite ones (a camera of extreme values) dropped, counted.
  return finish_read(in, cloud->size() + sink.non_finite(), sink, *cloud, report);
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
