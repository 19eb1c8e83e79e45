// scan_list.cpp - folders to natural-ordered file lists.
#include "odometry/scan_list.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <system_error>

#include "odometry/natural_order.hpp"
#include "ppcr/io.hpp"

namespace ppcr_odometry {
namespace {

// The extension of a file name, lower case ("scan.PLY" -> "ply").
std::string extension(const std::string& name) {
  std::string ext = std::filesystem::path(name).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The folder's most common extension among `names`, on a tie the first alphabetically; the files
// of other extensions move to *others.
void keep_one_format(std::vector<std::string>* names, std::vector<std::string>* others) {
  std::map<std::string, int> count;
  for (const std::string& name : *names) ++count[extension(name)];
  std::string chosen;
  int most = 0;
  for (const auto& [ext, n] : count) {
    if (n > most) chosen = ext, most = n;
  }
  std::vector<std::string> kept;
  for (std::string& name : *names) (extension(name) == chosen ? kept : *others).push_back(name);
  *names = std::move(kept);
}

ppcr::Status list_folder(const std::string& folder, std::vector<std::string>* scans,
                         std::vector<std::string>* skipped) {
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
        folder + ": no cloud file (.ply .pcd .xyz .txt .csv .pts .bin .png) in the folder");
  }
  std::sort(names.begin(), names.end(), natural_less);
  std::vector<std::string> others;
  keep_one_format(&names, &others);
  // Names that are times ("1305031229.6.png" and "1305031229.528784.png") in time order, which
  // natural order is not when their decimals differ in number.
  std::vector<double> times;
  if (times_from_names(names, &times)) {
    std::vector<std::size_t> order(names.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return times[a] < times[b]; });
    std::vector<std::string> sorted;
    for (std::size_t i : order) sorted.push_back(names[i]);
    names = std::move(sorted);
  }
  for (const std::string& name : names) {
    scans->push_back((std::filesystem::path(folder) / name).string());
  }
  if (skipped != nullptr && !others.empty()) {
    std::string line = folder + ": " + std::to_string(others.size()) + " file(s) not ." +
                       extension(names.front()) + " scans, skipped:";
    for (const std::string& name : others) line += " " + name;
    skipped->push_back(line);
  }
  return ppcr::Status::Ok();
}

// A TUM RGB-D folder (depth/ with depth.txt or rgb/ beside it): its depth images are the scans.
bool is_tum_rgbd_folder(const std::string& folder) {
  const std::filesystem::path path(folder);
  std::error_code error;
  return std::filesystem::is_directory(path / "depth", error) &&
         (std::filesystem::is_regular_file(path / "depth.txt", error) ||
          std::filesystem::is_directory(path / "rgb", error));
}

}  // namespace

bool times_from_names(const std::vector<std::string>& scans, std::vector<double>* times) {
  times->clear();
  for (const std::string& scan : scans) {
    const std::string stem = std::filesystem::path(scan).stem().string();
    const std::size_t point = stem.find('.');
    const auto digits = [&](std::size_t from, std::size_t to) {
      return to > from && std::all_of(stem.begin() + from, stem.begin() + to,
                                      [](char c) { return c >= '0' && c <= '9'; });
    };
    if (point == std::string::npos || !digits(0, point) || !digits(point + 1, stem.size())) {
      times->clear();
      return false;
    }
    times->push_back(std::stod(stem));
  }
  return !times->empty();
}

ppcr::Status list_scans(const std::vector<std::string>& inputs, std::vector<std::string>* scans,
                        std::vector<std::string>* skipped) {
  scans->clear();
  if (skipped != nullptr) skipped->clear();
  for (const std::string& input : inputs) {
    std::error_code error;
    if (std::filesystem::is_directory(input, error)) {
      const bool tum = is_tum_rgbd_folder(input);
      if (tum && skipped != nullptr) {
        skipped->push_back(input + ": a TUM RGB-D folder: its depth/ images are the scans");
      }
      const ppcr::Status s = list_folder(
          tum ? (std::filesystem::path(input) / "depth").string() : input, scans, skipped);
      if (!s.ok()) return s;
    } else {
      scans->push_back(input);
    }
  }
  return ppcr::Status::Ok();
}

}  // namespace ppcr_odometry
