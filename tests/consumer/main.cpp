// The README's example, built by tests/consumer as an outside project (find_package and
// add_subdirectory) linking ppcr::ppcr and ppcr::io: register a curved surface, read from a file,
// moved by a known transform, and check the result.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ppcr/io.hpp>
#include <ppcr/ppcr.hpp>
#include <string>

int main() {
  ppcr::PointCloud target;  // a wavy 1 m x 1 m surface, 2 cm spacing (metres)
  for (double x = -0.5; x <= 0.5; x += 0.02)
    for (double y = -0.5; y <= 0.5; y += 0.02)
      target.emplace_back(x, y, 0.1 * std::sin(4 * x) * std::cos(3 * y) + 0.05 * x * y);
  Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();  // maps source -> target
  T_true.rotate(Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.2, 0.3, 1).normalized()));
  T_true.translation() << 0.03, -0.02, 0.01;
  ppcr::PointCloud source;
  for (const Eigen::Vector3d& p : target) source.push_back(T_true.inverse() * p);
  // Through a file, as a user's clouds come.
  const std::string path =
      (std::filesystem::temp_directory_path() / "ppcr_consumer_target.ply").string();
  ppcr::Status s = ppcr::io::write_cloud(path, target);
  ppcr::PointCloud target_read;
  if (s.ok()) s = ppcr::io::read_cloud(path, &target_read);
  std::filesystem::remove(path);
  if (!s.ok()) return std::printf("%s\n", s.to_string().c_str()), 1;
#if defined(CONSUMER_NO_LZF)
  {  // Built without liblzf: a binary_compressed PCD is refused, naming what is missing.
    const std::string pcd =
        (std::filesystem::temp_directory_path() / "ppcr_consumer_compressed.pcd").string();
    if (std::FILE* f = std::fopen(pcd.c_str(), "wb")) {
      const char text[] =
          "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
          "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA binary_compressed\n";
      std::fwrite(text, 1, sizeof text - 1, f);
      const unsigned char sizes[8] = {4, 0, 0, 0, 12, 0, 0, 0};
      std::fwrite(sizes, 1, 8, f);
      std::fwrite("abcd", 1, 4, f);
      std::fclose(f);
    }
    ppcr::PointCloud compressed;
    const ppcr::Status c = ppcr::io::read_cloud(pcd, &compressed);
    std::filesystem::remove(pcd);
    std::printf("without liblzf: %s\n", c.to_string().c_str());
    if (c.ok() || c.message().find("liblzf") == std::string::npos) return 1;
  }
#endif

  ppcr::RegistrationOptions options;
  options.radius = 0.1;  // metres: larger than the initial misalignment
  const ppcr::RegistrationResult r = ppcr::align(source, target_read, options);
  if (!r.status.ok()) return std::printf("%s\n", r.status.to_string().c_str()), 1;
  const double rot = ppcr::rotation_error_deg(r.T_target_source, T_true);
  std::printf("%d iterations (%s), fitness %.3f, rotation error %.2e deg\n", r.iterations,
              ppcr::to_string(r.stop_reason), r.fitness, rot);
  return rot < 0.01 ? 0 : 1;
}
