// problems.cpp - the benchmark's problem-file reader.
#include "bench/problems.hpp"

#include <fstream>
#include <sstream>

#include "ppcr/se3.hpp"

namespace ppcr_bench {

ppcr::Status read_problems(const std::string& path, std::vector<Problem>* problems) {
  problems->clear();
  std::ifstream in(path);
  if (!in) return ppcr::Status(ppcr::StatusCode::kIoError, path + ": cannot open problem file");
  std::string line;
  int line_no = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    if (!header_seen) {  // the header line: `id source target overlap t1 ... t12`
      header_seen = true;
      if (line.compare(0, 2, "id") == 0) continue;
    }
    std::istringstream fields(line);
    Problem p;
    Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
    fields >> p.id >> p.source >> p.target >> p.overlap;
    for (int i = 0; i < 12 && fields; ++i) fields >> M(i / 4, i % 4);
    std::string extra;
    if (!fields || (fields >> extra)) {
      return ppcr::Status(
          ppcr::StatusCode::kParseError,
          path + ":" + std::to_string(line_no) +
              ": expected `id source target overlap t1 ... t12` (16 fields), got '" +
              line.substr(0, 120) + "'");
    }
    if (!ppcr::se3::is_rigid(M, 1e-5)) {
      return ppcr::Status(ppcr::StatusCode::kParseError, path + ":" + std::to_string(line_no) +
                                                             ": problem " + p.id +
                                                             ": t1..t12 is not a rigid transform");
    }
    p.T0.matrix() = M;
    p.T0 = ppcr::se3::orthonormalized(p.T0);
    problems->push_back(p);
  }
  if (problems->empty()) {
    return ppcr::Status(ppcr::StatusCode::kParseError, path + ": no problem found");
  }
  return ppcr::Status::Ok();
}

}  // namespace ppcr_bench
