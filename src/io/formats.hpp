// formats.hpp - the per-format readers and writers behind ppcr/io.hpp (private to ppcr_io).
//
// Readers take the whole file in memory, replace *cloud (cleared first) and fill *report
// (never null here). Writers stream to the path through a checked FileWriter.
#pragma once

#include <string>

#include "ppcr/abi.hpp"
#include "ppcr/io.hpp"
#include "reader_common.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

Status read_ply(const Input& in, PointCloud* cloud, ReadReport* report);
Status read_pcd(const Input& in, PointCloud* cloud, ReadReport* report);
Status read_xyz(const Input& in, PointCloud* cloud, ReadReport* report);
Status read_kitti_bin(const Input& in, PointCloud* cloud, ReadReport* report);
Status read_depth_png(const Input& in, const DepthCamera& camera, PointCloud* cloud,
                      ReadReport* report);

/// kInvalidArgument "<name>: depth camera <field> = <value> ..." for an unusable camera.
Status check_depth_camera(const std::string& name, const DepthCamera& camera);

Status write_ply(const std::string& path, const PointCloud& cloud);
Status write_pcd(const std::string& path, const PointCloud& cloud);
Status write_xyz(const std::string& path, const PointCloud& cloud);
Status write_kitti_bin(const std::string& path, const PointCloud& cloud);

/// The format named by the path's extension (.ply .pcd .xyz .txt .csv .pts .bin .png, any case),
/// else kAuto.
Format format_from_extension_impl(const std::string& path);

/// The format recognised from the first bytes, else kAuto.
Format format_from_content(const char* data, std::size_t size);

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
