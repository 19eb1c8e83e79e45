// xyz_writer.cpp - writes a cloud as XYZ text: one "x y z" line per point, each coordinate with
// 17 significant digits ("%.17g", locale-independent), which reads back bit-identically.
#include <string>

#include "file_access.hpp"
#include "formats.hpp"
#include "writer_common.hpp"

namespace ppcr {
inline namespace PPCR_ABI_NAMESPACE {
namespace io {
namespace detail {

Status write_xyz(const std::string& path, const PointCloud& cloud) {
  Status status = check_finite_cloud(path, cloud);
  if (!status.ok()) return status;
  FileWriter out;
  status = out.open(path);
  if (!status.ok()) return status;
  char line[3 * (kMaxDoubleChars + 1)];
  for (const Eigen::Vector3d& p : cloud) {
    std::size_t n = 0;
    for (int axis = 0; axis < 3; ++axis) {
      n += format_double(p[axis], line + n);
      line[n++] = axis < 2 ? ' ' : '\n';
    }
    out.append(line, n);
  }
  return out.finish();
}

}  // namespace detail
}  // namespace io
}  // namespace PPCR_ABI_NAMESPACE
}  // namespace ppcr
