// pcd_writer.cpp - writes a cloud as PCD v0.7 DATA binary with double x y z (FIELDS x y z,
// SIZE 8, TYPE F, an unorganized cloud: WIDTH = POINTS, HEIGHT 1, identity VIEWPOINT).
#include <cstring>
#include <string>

#include "file_access.hpp"
#include "formats.hpp"
#include "writer_common.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

Status write_pcd(const std::string& path, const PointCloud& cloud) {
  Status status = check_finite_cloud(path, cloud);
  if (!status.ok()) return status;
  FileWriter out;
  status = out.open(path);
  if (!status.ok()) return status;
  const std::string n = std::to_string(cloud.size());
  out.append(
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n"
      "FIELDS x y z\n"
      "SIZE 8 8 8\n"
      "TYPE F F F\n"
      "COUNT 1 1 1\n"
      "WIDTH " +
      n +
      "\n"
      "HEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS " +
      n +
      "\n"
      "DATA binary\n");
  // PCD binary data are little endian, like the host (checked in scalar_type.cpp).
  for (const Eigen::Vector3d& p : cloud) {
    unsigned char record[3 * sizeof(double)];
    std::memcpy(record, p.data(), sizeof(record));
    out.append(record, sizeof(record));
  }
  return out.finish();
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
