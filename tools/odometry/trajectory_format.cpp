// trajectory_format.cpp - KITTI and TUM lines, written and read.
#include "odometry/trajectory_format.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ppcr_odometry {
namespace {

constexpr double kTolerance = 1e-4;
constexpr double kExact = 1e-12;  // below this a rotation is kept as read

// The shortest of 15-17 significant digits that reads back as `value`: exact, and a timestamp
// read from "1305031229.564442" is written as such.
void append(std::string* line, double value) {
  char text[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  if (!line->empty()) *line += ' ';
  *line += text;
}

ppcr::Status parse_error(const std::string& path, int line, const std::string& what) {
  return ppcr::Status(ppcr::StatusCode::kParseError,
                      path + ":" + std::to_string(line) + ": " + what);
}

// The pose of one data line of `count` numbers (12: KITTI, 8: TUM), or an error.
ppcr::Status parse_pose(const std::vector<double>& v, const std::string& path, int line,
                        double* time, Eigen::Isometry3d* pose) {
  *pose = Eigen::Isometry3d::Identity();
  if (v.size() == 12) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) pose->matrix()(r, c) = v[static_cast<std::size_t>(4 * r + c)];
    }
    const Eigen::Matrix3d R = pose->linear();
    const double deviation = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
    if (!(deviation <= kTolerance) || !(R.determinant() > 0.0)) {
      return parse_error(path, line,
                         "the rotation is not orthonormal (R^T R deviates from I by " +
                             std::to_string(deviation) + ")");
    }
    if (deviation > kExact) {
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
      pose->linear() = svd.matrixU() * svd.matrixV().transpose();
    }
    *time = 0.0;
    return ppcr::Status::Ok();
  }
  Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
  if (!(std::abs(q.norm() - 1.0) <= kTolerance)) {
    return parse_error(path, line,
                       "the quaternion's norm is " + std::to_string(q.norm()) + ", not 1");
  }
  q.normalize();
  pose->linear() = q.toRotationMatrix();
  pose->translation() = Eigen::Vector3d(v[1], v[2], v[3]);
  *time = v[0];
  return ppcr::Status::Ok();
}

}  // namespace

std::string kitti_line(const Eigen::Isometry3d& pose) {
  std::string line;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) append(&line, pose.matrix()(r, c));
  }
  return line;
}

std::string tum_line(double time, const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.rotation());
  std::string line;
  append(&line, time);
  for (int i = 0; i < 3; ++i) append(&line, pose.translation()[i]);
  for (const double value : {q.x(), q.y(), q.z(), q.w()}) append(&line, value);
  return line;
}

ppcr::Status read_trajectory(const std::string& path, Trajectory* trajectory) {
  std::ifstream file(path);
  if (!file) return ppcr::Status(ppcr::StatusCode::kIoError, path + ": cannot read");
  *trajectory = Trajectory();
  std::size_t columns = 0;
  std::string text;
  for (int line = 1; std::getline(file, text); ++line) {
    const std::size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    std::istringstream fields(text);
    std::vector<double> values;
    std::string field;
    while (fields >> field) {
      char* end = nullptr;
      const double value = std::strtod(field.c_str(), &end);
      if (*end != '\0' || !std::isfinite(value)) {
        return parse_error(path, line, "'" + field + "' is not a finite number");
      }
      values.push_back(value);
    }
    if (values.empty()) continue;
    if (columns == 0 && (values.size() == 12 || values.size() == 8)) columns = values.size();
    if (values.size() != columns) {
      return parse_error(
          path, line,
          std::to_string(values.size()) + " numbers; expected " +
              (columns == 0 ? std::string("12 (KITTI) or 8 (TUM)") : std::to_string(columns)));
    }
    double time = 0.0;
    Eigen::Isometry3d pose;
    const ppcr::Status s = parse_pose(values, path, line, &time, &pose);
    if (!s.ok()) return s;
    trajectory->times.push_back(columns == 12 ? static_cast<double>(trajectory->poses.size())
                                              : time);
    trajectory->poses.push_back(pose);
  }
  if (trajectory->poses.empty()) {
    return ppcr::Status(ppcr::StatusCode::kParseError, path + ": no pose in the file");
  }
  trajectory->timed = columns == 8;
  return ppcr::Status::Ok();
}

}  // namespace ppcr_odometry
