// problems.hpp - problem files of the point clouds registration benchmark (Fontana et al. 2020):
// a header line, then per line `id source target overlap t1 ... t12`, t1..t12 the first three
// rows of the initial misplacement T0; paths relative to the problem file's folder or a data root.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "ppcr/status.hpp"

namespace ppcr_bench {

struct Problem {
  std::string id;
  std::string source;  // path as written in the file
  std::string target;
  double overlap = 0.0;
  Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();  // initial misplacement of the source
};

/// Reads every problem; errors name the file, the line and the field.
ppcr::Status read_problems(const std::string& path, std::vector<Problem>* problems);

}  // namespace ppcr_bench
