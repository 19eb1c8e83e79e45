// scan_list.cpp - folders to natural-ordered file lists.
#include "odometry/scan_list.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "odometry/natural_order.hpp"
#include "ppcr/io.hpp"

namespace ppcr_odometry {
namespace {

ppcr::Status list_folder(const std::string& folder, std::vector<std::string>* scans) {
  std::error_code error;
  std::vector<std::string> names;
  for (std::filesystem::directory_iterator it(folder, error), end; !error && it != end;
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || name[0] == '.' || !it->is_regular_file(error)) continue;
    if (ppcr::io::format_from_extension(name) == ppcr::io::Format::kAuto) continue;
    names.push_back(name);
  }
  if (error) {
    return ppcr::Status(ppcr::StatusCode::kIoError,
                        folder + ": cannot list the folder: " + error.message());
  }
  if (names.empty()) {
    return ppcr::Status(
        ppcr::StatusCode::kIoError,
        folder + ": no cloud file (.ply .pcd .xyz .txt .csv .pts .bin) in the folder");
  }
  std::sort(names.begin(), names.end(), natural_less);
  for (const std::string& name : names) {
    scans->push_back((std::filesystem::path(folder) / name).string());
  }
  return ppcr::Status::Ok();
}

}  // namespace

ppcr::Status list_scans(const std::vector<std::string>& inputs, std::vector<std::string>* scans) {
  scans->clear();
  for (const std::string& input : inputs) {
    std::error_code error;
    if (std::filesystem::is_directory(input, error)) {
      const ppcr::Status s = list_folder(input, scans);
      if (!s.ok()) return s;
    } else {
      scans->push_back(input);
    }
  }
  return ppcr::Status::Ok();
}

}  // namespace ppcr_odometry
