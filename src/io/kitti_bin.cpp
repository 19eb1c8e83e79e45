// kitti_bin.cpp - KITTI Velodyne scans (.bin): no header, one 16-byte record per point, float32
// x, y, z, intensity, little endian (the layout of the KITTI odometry benchmark's velodyne/*.bin
// and of the tools that write it). The file size must be a whole number of records. Intensity is
// not kept on reading and is written as 0. Writing rounds each coordinate to float32.
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "file_access.hpp"
#include "formats.hpp"
#include "scalar_type.hpp"
#include "writer_common.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {
namespace {

constexpr std::size_t kRecordBytes = 16;  // float32 x, y, z, intensity

void store_f32_le(float value, unsigned char* p) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(bits >> (8 * i));
}

}  // namespace

Status read_kitti_bin(const Input& in, PointCloud* cloud, ReadReport* report) {
  cloud->clear();
  report->format = Format::kKittiBin;
  report->encoding = "binary_little_endian";
  if (in.size % kRecordBytes != 0) {
    return parse_error(in, std::to_string(in.size) +
                               " bytes is not a whole number of 16-byte KITTI records (float32 "
                               "x, y, z, intensity): " +
                               std::to_string(in.size / kRecordBytes) + " records and " +
                               std::to_string(in.size % kRecordBytes) + " bytes left over");
  }
  const std::size_t n = in.size / kRecordBytes;
  cloud->reserve(n);
  PointSink sink(cloud);
  const ScalarLoader load = scalar_loader(ScalarType::kFloat32, ByteOrder::kLittleEndian);
  const unsigned char* record = in.bytes();
  for (std::size_t i = 0; i < n; ++i, record += kRecordBytes) {
    sink.add(load(record), load(record + 4), load(record + 8));
  }
  return finish_read(in, n, sink, *cloud, report);
}

Status write_kitti_bin(const std::string& path, const PointCloud& cloud) {
  Status status = check_finite_cloud(path, cloud);
  if (!status.ok()) return status;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud[i].cwiseAbs().maxCoeff() > std::numeric_limits<float>::max()) {
      return Status(StatusCode::kInvalidArgument,
                    path + ": point " + std::to_string(i) +
                        " has a coordinate beyond float32's range, which a KITTI .bin stores");
    }
  }
  FileWriter out;
  status = out.open(path);
  if (!status.ok()) return status;
  unsigned char record[kRecordBytes] = {};
  for (const Eigen::Vector3d& p : cloud) {
    for (int axis = 0; axis < 3; ++axis) {
      store_f32_le(static_cast<float>(p[axis]), record + 4 * axis);
    }
    out.append(record, kRecordBytes);  // intensity: the last 4 bytes, 0
  }
  return out.finish();
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
