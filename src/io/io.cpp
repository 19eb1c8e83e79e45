// io.cpp - the public entry points of ppcr_io (ppcr/io.hpp): format choice and dispatch to the
// per-format readers and writers, with exceptions contained (see guard.hpp).
#include "ppcr/io.hpp"

#include <cstdint>
#include <string>
#include <utility>

#include "file_access.hpp"
#include "formats.hpp"
#include "guard.hpp"
#include "text_scan.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace {

// A regular cloud file is bounded by memory only (a failed allocation is reported); a pipe is
// read up to 1 GiB, so that a writer that never stops cannot exhaust memory.
constexpr detail::ReadLimits kCloudLimits{UINT64_MAX, std::uint64_t{1} << 30, "a point cloud"};

// Depth images need libpng; a build without it says so.
Status read_depth_image(const detail::Input& in, const DepthCamera& camera, PointCloud* cloud,
                        ReadReport* report) {
#ifdef PPCR_IO_HAVE_PNG
  return detail::read_depth_png(in, camera, cloud, report);
#else
  (void)camera, (void)cloud, (void)report;
  return Status(StatusCode::kIoError,
                in.name +
                    ": a depth image (PNG), which this build of ppcr_io cannot read: it "
                    "was built without libpng");
#endif
}

Status read_buffer(const std::string& name, const char* data, std::size_t size, Format format,
                   const DepthCamera& camera, PointCloud* cloud, ReadReport* report) {
  if (size == 0) return Status(StatusCode::kParseError, name + ": file is empty (0 bytes)");
  if (data == nullptr) {
    return Status(StatusCode::kInvalidArgument,
                  name + ": null data pointer with size " + std::to_string(size));
  }
  if (format == Format::kAuto) format = detail::format_from_extension_impl(name);
  if (format == Format::kAuto) format = detail::format_from_content(data, size);
  const detail::Input in{name, data, size};
  switch (format) {
    case Format::kPly:
      return detail::read_ply(in, cloud, report);
    case Format::kPcd:
      return detail::read_pcd(in, cloud, report);
    case Format::kXyz:
      return detail::read_xyz(in, cloud, report);
    case Format::kKittiBin:
      return detail::read_kitti_bin(in, cloud, report);
    case Format::kDepthPng:
      return read_depth_image(in, camera, cloud, report);
    case Format::kAuto:
      break;
  }
  return Status(StatusCode::kParseError,
                name +
                    ": unknown point cloud format: the extension is not .ply .pcd .xyz .txt "
                    ".csv .pts .bin (KITTI) or .png (depth), and the first bytes '" +
                    detail::escape_for_message(std::string_view(data, size), 24) +
                    "' are neither a PLY nor a PCD header nor numbers");
}

}  // namespace

const char* to_string(Format format) {
  switch (format) {
    case Format::kAuto:
      return "auto";
    case Format::kPly:
      return "ply";
    case Format::kPcd:
      return "pcd";
    case Format::kXyz:
      return "xyz";
    case Format::kKittiBin:
      return "kitti_bin";
    case Format::kDepthPng:
      return "depth_png";
  }
  return "unknown";
}

Format format_from_extension(const std::string& path) {
  return detail::format_from_extension_impl(path);
}

Status read_cloud_from_buffer(const std::string& name, const char* data, std::size_t size,
                              Format format, PointCloud* cloud, ReadReport* report,
                              const DepthCamera& camera) {
  Status status = detail::guarded(name, [&]() -> Status {
    if (cloud == nullptr) {
      return Status(StatusCode::kInvalidArgument, name + ": null output cloud");
    }
    ReadReport local;
    Status read_status = read_buffer(name, data, size, format, camera, cloud, &local);
    if (report != nullptr) *report = std::move(local);
    return read_status;
  });
  // Never a partial cloud on failure (also when an exception, e.g. bad_alloc, was contained).
  if (!status.ok() && cloud != nullptr) cloud->clear();
  return status;
}

namespace {

// read_cloud with a camera for depth images.
Status read_file(const std::string& path, Format format, const DepthCamera& camera,
                 PointCloud* cloud, ReadReport* report) {
  Status status = detail::guarded(path, [&]() -> Status {
    if (cloud == nullptr) {
      return Status(StatusCode::kInvalidArgument, path + ": null output cloud");
    }
    cloud->clear();
    if (report != nullptr) *report = ReadReport();
    std::string bytes;
    Status file_status = detail::read_file_bytes(path, kCloudLimits, &bytes);
    if (!file_status.ok()) return file_status;
    return read_cloud_from_buffer(path, bytes.data(), bytes.size(), format, cloud, report, camera);
  });
  if (!status.ok() && cloud != nullptr) cloud->clear();
  return status;
}

}  // namespace

Status read_cloud(const std::string& path, PointCloud* cloud, ReadReport* report, Format format) {
  return read_file(path, format, DepthCamera(), cloud, report);
}

Status read_cloud(const std::string& path, const DepthCamera& camera, PointCloud* cloud,
                  ReadReport* report) {
  return read_file(path, Format::kAuto, camera, cloud, report);
}

Status write_cloud(const std::string& path, const PointCloud& cloud, Format format) {
  return detail::guarded(path, [&]() -> Status {
    const Format chosen =
        format == Format::kAuto ? detail::format_from_extension_impl(path) : format;
    switch (chosen) {
      case Format::kPly:
        return detail::write_ply(path, cloud);
      case Format::kPcd:
        return detail::write_pcd(path, cloud);
      case Format::kXyz:
        return detail::write_xyz(path, cloud);
      case Format::kKittiBin:
        return detail::write_kitti_bin(path, cloud);
      case Format::kDepthPng:
        return Status(StatusCode::kInvalidArgument,
                      path +
                          ": depth images (.png) are read, not written: choose .ply, .pcd, "
                          ".xyz, .txt, .csv, .pts or .bin");
      case Format::kAuto:
        break;
    }
    return Status(StatusCode::kInvalidArgument,
                  path +
                      ": cannot choose an output format from the extension (expected .ply, "
                      ".pcd, .xyz, .txt, .csv, .pts or .bin), and none was given");
  });
}

}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
