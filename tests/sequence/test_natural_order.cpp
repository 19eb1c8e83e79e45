// Natural order of scan names, and folders listed in it (tools/odometry/natural_order, scan_list).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "odometry/natural_order.hpp"
#include "odometry/scan_list.hpp"

using ppcr_odometry::natural_less;

TEST_CASE("numbers in names compare by value") {
  CHECK(natural_less("scan_2", "scan_10"));
  CHECK(!natural_less("scan_10", "scan_2"));
  CHECK(natural_less("scan_9.ply", "scan_10.ply"));
  CHECK(natural_less("scan_000009.ply", "scan_000010.ply"));
  CHECK(natural_less("a2b3", "a2b11"));
  CHECK(natural_less("scan_99999999999999999999998", "scan_99999999999999999999999"));
  CHECK(natural_less("b", "c"));
  CHECK(natural_less("scan", "scan_1"));  // a prefix first
}

TEST_CASE("the order is strict: equal values differ by leading zeros, then bytes") {
  CHECK(natural_less("scan_2", "scan_02"));
  CHECK(!natural_less("scan_02", "scan_2"));
  CHECK(!natural_less("scan_2", "scan_2"));
  std::vector<std::string> names{"s_10", "s_2", "s_02", "s_1", "s_001", "s_20", "t", "s_3"};
  std::sort(names.begin(), names.end(), natural_less);
  CHECK(names ==
        std::vector<std::string>{"s_1", "s_001", "s_2", "s_02", "s_3", "s_10", "s_20", "t"});
}

TEST_CASE("a folder lists the scans of its most common format in natural order, files as given") {
  const std::filesystem::path dir =
      std::filesystem::path(PPCR_SEQUENCE_TEST_DIR) / "natural_order_folder";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* name : {"scan_10.ply", "scan_2.PLY", "scan_1.ply", "notes.md", ".hidden.ply",
                           "truth.txt", "scan_11.pcd"}) {
    std::ofstream(dir / name) << "x";
  }
  std::filesystem::create_directories(dir / "sub.ply");  // a folder, not a file
  std::vector<std::string> scans, skipped;
  REQUIRE(ppcr_odometry::list_scans({dir.string(), "extra.pcd"}, &scans, &skipped).ok());
  const std::vector<std::string> expected{(dir / "scan_1.ply").string(),
                                          (dir / "scan_2.PLY").string(),
                                          (dir / "scan_10.ply").string(), "extra.pcd"};
  CHECK(scans == expected);
  // The other cloud formats are skipped, in one line naming them.
  REQUIRE(skipped.size() == 1u);
  CHECK(skipped[0] == dir.string() + ": 2 file(s) not .ply scans, skipped: scan_11.pcd truth.txt");

  // A synthetic sequence's folder: the .xyz scans and, beside them, its ground truth as .txt.
  const std::filesystem::path xyz = dir / "xyz";
  std::filesystem::create_directories(xyz);
  for (const char* name : {"scan_0.xyz", "scan_1.xyz", "scan_2.xyz", "gt_kitti.txt", "gt.txt"}) {
    std::ofstream(xyz / name) << "x";
  }
  REQUIRE(ppcr_odometry::list_scans({xyz.string()}, &scans).ok());
  CHECK(scans == std::vector<std::string>{(xyz / "scan_0.xyz").string(),
                                          (xyz / "scan_1.xyz").string(),
                                          (xyz / "scan_2.xyz").string()});

  const std::filesystem::path empty = dir / "empty";
  std::filesystem::create_directories(empty);
  const ppcr::Status s = ppcr_odometry::list_scans({empty.string()}, &scans);
  CHECK(!s.ok());
  CHECK(s.message().find(empty.string()) != std::string::npos);

  // A KITTI velodyne/ folder: 000000.bin, 000001.bin, ... (and its calibration text beside).
  const std::filesystem::path kitti = dir / "velodyne";
  std::filesystem::create_directories(kitti);
  for (const char* name : {"000010.bin", "000002.bin", "000001.BIN", "README"}) {
    std::ofstream(kitti / name) << "x";
  }
  REQUIRE(ppcr_odometry::list_scans({kitti.string()}, &scans).ok());
  CHECK(scans == std::vector<std::string>{(kitti / "000001.BIN").string(),
                                          (kitti / "000002.bin").string(),
                                          (kitti / "000010.bin").string()});
}

TEST_CASE("a TUM RGB-D folder's scans are its depth images, their names their times") {
  const std::filesystem::path dir = std::filesystem::path(PPCR_SEQUENCE_TEST_DIR) / "tum_folder";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "depth");
  std::filesystem::create_directories(dir / "rgb");
  for (const char* name : {"groundtruth.txt", "rgb.txt", "rgb/1305031229.5.png"}) {
    std::ofstream(dir / name) << "x";
  }
  // Times with other numbers of decimals, in time order (not natural order: .6 after .564442).
  for (const char* name :
       {"1305031229.564442.png", "1305031229.528784.png", "1305031230.1.png", "1305031229.6.png"}) {
    std::ofstream(dir / "depth" / name) << "x";
  }
  std::vector<std::string> scans, skipped;
  REQUIRE(ppcr_odometry::list_scans({dir.string()}, &scans, &skipped).ok());
  CHECK(scans == std::vector<std::string>{(dir / "depth/1305031229.528784.png").string(),
                                          (dir / "depth/1305031229.564442.png").string(),
                                          (dir / "depth/1305031229.6.png").string(),
                                          (dir / "depth/1305031230.1.png").string()});
  REQUIRE(skipped.size() == 1u);  // says which folder it read
  CHECK(skipped[0] == dir.string() + ": a TUM RGB-D folder: its depth/ images are the scans");
  std::vector<double> times;
  REQUIRE(ppcr_odometry::times_from_names(scans, &times));
  CHECK(times ==
        std::vector<double>{1305031229.528784, 1305031229.564442, 1305031229.6, 1305031230.1});
  // A depth/ subfolder alone (no depth.txt, no rgb/) is not a TUM folder: its own files count.
  const std::filesystem::path plain = dir / "plain";
  std::filesystem::create_directories(plain / "depth");
  std::ofstream(plain / "scan_1.ply") << "x";
  std::ofstream(plain / "scan_2.ply") << "x";
  REQUIRE(ppcr_odometry::list_scans({plain.string()}, &scans).ok());
  CHECK(scans.size() == 2u);
  // Names that are not all times give none: KITTI's numbers, a name without digits after the point.
  for (const auto& names : {std::vector<std::string>{"a/000000.bin", "a/000001.bin"},
                            std::vector<std::string>{"1305031229.5.png", "scan_1.5.png"},
                            std::vector<std::string>{"1305031229..png"}}) {
    CHECK_FALSE(ppcr_odometry::times_from_names(names, &times));
    CHECK(times.empty());
  }
}
