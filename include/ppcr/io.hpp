// io.hpp - ppcr_io: reading and writing point clouds (PLY, PCD, XYZ/CSV, KITTI .bin; depth
// images read as clouds).
//
// A separate library (target ppcr::io) so embedded users of the core can leave it out.
// Like the core, it never throws across its API and never prints: each call returns a Status whose
// message names the file, the line or byte offset, and what was expected.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <string>

#include "ppcr/abi.hpp"
#include "ppcr/status.hpp"
#include "ppcr/types.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {

/// kKittiBin: KITTI Velodyne scans (.bin), float32 x, y, z, intensity per point, little endian.
/// kDepthPng: a depth image (16-bit grayscale PNG), back-projected through a DepthCamera (read
/// only).
enum class Format { kAuto, kPly, kPcd, kXyz, kKittiBin, kDepthPng };

/// A depth camera: pinhole intrinsics (pixels) and the depth scale (stored value per metre, or per
/// cloud unit). A pixel (u, v) (column, row, from 0 at the top-left pixel's centre) storing d > 0
/// is the point ((u - cx) z / fx, (v - cy) z / fy, z), z = d / depth_scale, in the camera frame
/// (x right, y down, z forward); d = 0 is "no reading" and gives no point.
/// The defaults are TUM RGB-D's defaults for its Kinect data (its "ROS default" intrinsics, depth
/// stored x5000); its Freiburg 1 frames are fx 517.3, fy 516.5, cx 318.6, cy 255.3. A camera
/// storing millimetres (Redwood, Azure Kinect, RealSense at its default) has depth_scale 1000.
struct DepthCamera {
  double fx = 525.0;
  double fy = 525.0;
  double cx = 319.5;
  double cy = 239.5;
  double depth_scale = 5000.0;
};

/// What a reader saw, beyond the points it returned.
struct ReadReport {
  Format format = Format::kAuto;  // the format actually read
  std::string encoding;  // "ascii", "binary_little_endian", "binary", "binary_compressed"...
  std::size_t points_in_file = 0;      // points the file holds (header count, or data rows)
  std::size_t non_finite_dropped = 0;  // points with a NaN/Inf coordinate, dropped and counted
};

/// Reads a cloud. Format::kAuto picks by extension (.ply .pcd .xyz .txt .csv .pts .bin .png,
/// case-insensitive) and, when the extension is unknown, by the file's first bytes ("ply" line;
/// "# .PCD", VERSION or FIELDS; the PNG signature; numbers). Coordinates are read as double; points
/// with a non-finite coordinate are dropped and counted in report->non_finite_dropped. A file
/// holding zero finite points is an error (kEmptyCloud). The file is read whole into memory first.
/// A UTF-8 byte-order mark at the start is skipped in every format. Devices (/dev/zero,
/// /dev/urandom, a terminal) are refused (kIoError); a pipe is read up to 1 GiB, more is refused.
/// On any error *cloud is left empty; *report (if given) holds what was learnt before the error.
///
/// Formats read:
///  - PLY ascii / binary_little_endian / binary_big_endian: x y z of element "vertex", of any
///    numeric type; other properties (also lists) and other elements (faces...) are skipped.
///  - PCD v0.7 (and .5/.6 headers) DATA ascii / binary / binary_compressed (LZF): fields x y z of
///    any TYPE/SIZE/COUNT; organized clouds are read row after row (NaN padding dropped). Zero
///    bytes after the points (the padding PCL's command-line tools write) are accepted; any
///    other trailing byte is refused with the count of extra bytes.
///  - XYZ/CSV/PTS text: one point per line, fields separated by blanks or by commas, the first
///    three are x y z, every line has the same number (>= 3) of numeric fields; blank lines and
///    '#' comments are skipped. The FIRST non-comment line may instead be a header of column
///    names (no numeric field) or a PTS point count (one integer, checked against the data).
///    A header naming x, y and z (any case, CloudCompare's "//X" too) selects those columns
///    ("nx,ny,nz,x,y,z"); one naming none of them keeps the first three; data lines must have as
///    many fields as it names. A decimal comma ("1,5 2,0 3,25"), a thousands separator
///    ("5,632.500 1 2") or ';'-separated fields are refused (kParseError with the line, the
///    column and the text), never guessed. A line of more than 64 fields is refused.
///  - KITTI .bin (by extension only: it has no header): records of float32 x y z intensity,
///    little endian; a size that is not a whole number of 16-byte records is refused (kParseError
///    with the size and the bytes left over). Intensity is not kept.
///  - Depth images (.png, through libpng): 16-bit grayscale, not interlaced; each pixel with a
///    non-zero value becomes a point, back-projected through the DepthCamera (this overload: the
///    defaults, TUM's; the next one takes yours). Another kind of PNG (8-bit, colour, palette)
///    is refused naming its kind; an image without any depth is kEmptyCloud. report->
///    points_in_file counts the pixels with depth. A build without libpng refuses depth images
///    (kIoError saying so).
Status read_cloud(const std::string& path, PointCloud* cloud, ReadReport* report = nullptr,
                  Format format = Format::kAuto);

/// Like read_cloud, a depth image back-projected through `camera` (other formats ignore it). A
/// camera field that is not finite, or an fx, fy or depth_scale not > 0, is kInvalidArgument
/// naming the field and its value.
Status read_cloud(const std::string& path, const DepthCamera& camera, PointCloud* cloud,
                  ReadReport* report = nullptr);

/// Like read_cloud, from `size` bytes at `data` (need not be NUL-terminated; nothing past
/// data + size is read). `name` stands for the file in messages and, with Format::kAuto, gives
/// the extension. size == 0 is an error (kParseError: empty file). No file is touched.
Status read_cloud_from_buffer(const std::string& name, const char* data, std::size_t size,
                              Format format, PointCloud* cloud, ReadReport* report = nullptr,
                              const DepthCamera& camera = DepthCamera());

/// The format a path's extension names (.ply .pcd .xyz .txt .csv .pts .bin .png, any case), else
/// kAuto.
Format format_from_extension(const std::string& path);

/// Writes a cloud. Format::kAuto picks by extension. PLY is written binary little endian with
/// double x y z, PCD binary with double x y z, XYZ as ASCII text with 17 significant digits, so
/// that every round trip is exact; KITTI .bin as float32 x y z with intensity 0 (coordinates
/// rounded to float32; one beyond its range is refused). Depth images are not written
/// (kInvalidArgument). A cloud with a non-finite coordinate is refused
/// (kInvalidArgument: readers would drop the point); an empty cloud is written as a valid file
/// with zero points. Write failures (cannot create, disk full...) give kIoError naming the path,
/// and the partial file is removed.
Status write_cloud(const std::string& path, const PointCloud& cloud, Format format = Format::kAuto);

/// Reads a rigid transform: 16 numbers (a 4x4 matrix, row by row) or 12 (its top 3 rows, the last
/// row being 0 0 0 1), separated by blanks/newlines; '#' starts a comment to the end of the line.
/// A file over 1 MiB is refused before it is read; devices are refused, pipes read up to 1 MiB.
/// The matrix must be rigid, as ppcr::se3::is_rigid(M, 1e-6) decides (R^T R = I and det R = +1
/// within 1e-6), with the last row 0 0 0 1 within 1e-9; otherwise kParseError says what is wrong
/// (e.g. "R^T R deviates from I by 0.03"). The values are kept as written (not re-orthonormalised),
/// except that the last row is set to exactly 0 0 0 1.
Status read_transform(const std::string& path, Eigen::Isometry3d* T);

/// Like read_transform, from bytes in memory; `name` stands for the file in messages.
Status read_transform_from_buffer(const std::string& name, const char* data, std::size_t size,
                                  Eigen::Isometry3d* T);

/// Writes T as 4 lines of 4 numbers with 17 significant digits (an exact round trip through
/// read_transform). Refuses (kInvalidArgument) a non-finite or non-rigid T.
Status write_transform(const std::string& path, const Eigen::Isometry3d& T);

const char* to_string(Format format);

}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
