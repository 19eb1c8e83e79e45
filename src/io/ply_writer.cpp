// ply_writer.cpp - writes a cloud as binary little-endian PLY with double x y z (24 bytes per
// vertex), so that reading it back gives bit-identical coordinates.
#include <cstring>
#include <string>

#include "file_access.hpp"
#include "formats.hpp"
#include "writer_common.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

Status write_ply(const std::string& path, const PointCloud& cloud) {
  Status status = check_finite_cloud(path, cloud);
  if (!status.ok()) return status;
  FileWriter out;
  status = out.open(path);
  if (!status.ok()) return status;
  out.append(
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment written by ppcr_io\n"
      "element vertex " +
      std::to_string(cloud.size()) +
      "\n"
      "property double x\n"
      "property double y\n"
      "property double z\n"
      "end_header\n");
  // The host is little endian (checked in scalar_type.cpp), so the doubles go out as they are.
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
