// Files written by the tools users have (../shared/data/io: PCL 1.13's PCDWriter and PLYWriter,
// PCL's command-line tools, Open3D 0.16, CSVs with a header row): every file listed in
// MANIFEST.json reads with the manifest's finite point count, first finite point and centroid.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "ppcr/io.hpp"
#include "test_data.hpp"

namespace {

Eigen::Vector3d vector3(const nlohmann::json& value) {
  return Eigen::Vector3d(value.at(0).get<double>(), value.at(1).get<double>(),
                         value.at(2).get<double>());
}

nlohmann::json load_manifest(const std::string& folder) {
  const std::string path = folder + "/MANIFEST.json";
  std::ifstream in(path);
  INFO("manifest " << path);
  REQUIRE(in.good());
  return nlohmann::json::parse(in);
}

void check_file(const std::string& folder, const std::string& name, const nlohmann::json& entry,
                double tolerance) {
  const std::string path = folder + "/" + name;
  ppcr::PointCloud cloud;
  ppcr::io::ReadReport report;
  const ppcr::Status s = ppcr::io::read_cloud(path, &cloud, &report);
  INFO(path << " (" << entry.at("writer").get<std::string>() << "): " << s.to_string());
  REQUIRE(s.ok());
  REQUIRE(cloud.size() == entry.at("points").get<std::size_t>());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : cloud) centroid += p;
  centroid /= static_cast<double>(cloud.size());
  const Eigen::Vector3d first = vector3(entry.at("first"));
  const Eigen::Vector3d expected_centroid = vector3(entry.at("centroid"));
  INFO("first " << cloud[0].transpose() << " expected " << first.transpose());
  CHECK((cloud[0] - first).cwiseAbs().maxCoeff() <= tolerance);
  INFO("centroid " << centroid.transpose() << " expected " << expected_centroid.transpose());
  CHECK((centroid - expected_centroid).cwiseAbs().maxCoeff() <= tolerance);
}

}  // namespace

TEST_CASE("Every file from PCL 1.13, PCL's tools and Open3D 0.16 reads as its manifest says",
          "[io][real_data][writers]") {
  const std::string folder = ppcr_test::data_path("io");
  const nlohmann::json manifest = load_manifest(folder);
  const double tolerance = manifest.at("tolerance").get<double>();
  const nlohmann::json& files = manifest.at("files");
  REQUIRE(files.size() >= 30u);
  for (auto it = files.begin(); it != files.end(); ++it) {
    SECTION(it.key()) { check_file(folder, it.key(), it.value(), tolerance); }
  }
}

TEST_CASE("The manifest lists every cloud in the folder", "[io][real_data][writers]") {
  const std::string folder = ppcr_test::data_path("io");
  const nlohmann::json files = load_manifest(folder).at("files");
  std::string unlisted;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name != "MANIFEST.json" && name != "README.md" && !files.contains(name)) {
      unlisted += " " + name;
    }
  }
  INFO("files in " << folder
                   << " that MANIFEST.json does not list (no test reads them):" << unlisted);
  CHECK(unlisted.empty());
}
