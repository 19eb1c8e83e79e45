// association_reference.hpp - the independent reference for association tests: a brute-force
// radius-limited kNN of every transformed source point, compared with an AssociationTable.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "association/association_table.hpp"
#include "ppcr/types.hpp"

namespace core_test {

// Compares the table with brute force; returns "" or the first mismatch.
inline std::string table_mismatch(const ppcr::detail::AssociationTable& table,
                                  const ppcr::PointCloud& source, const ppcr::PointCloud& target,
                                  const Eigen::Isometry3d& T, double radius_sq) {
  const std::size_t k = static_cast<std::size_t>(table.k);
  std::size_t pairs = 0, matched = 0;
  std::vector<double> in_range;
  for (std::size_t j = 0; j < source.size(); ++j) {
    const Eigen::Vector3d p = T.linear() * source[j] + T.translation();
    in_range.clear();
    for (const Eigen::Vector3d& y : target) {
      const double d = (y - p).squaredNorm();
      if (d <= radius_sq) in_range.push_back(d);
    }
    std::sort(in_range.begin(), in_range.end());
    const std::size_t expected = std::min(in_range.size(), k);
    std::ostringstream why;
    why << "source point " << j << ": ";
    if (table.count[j] != expected) {
      why << "count " << table.count[j] << ", brute force " << expected;
      return why.str();
    }
    pairs += expected;
    matched += expected > 0;
    for (std::size_t m = 0; m < expected; ++m) {
      const std::uint32_t idx = table.index[j * k + m];
      if (idx >= target.size()) return why.str() + "index out of range";
      const double d = (target[idx] - p).squaredNorm();
      if (std::abs(d - in_range[m]) > 1e-12 * (1.0 + d)) {
        why << "slot " << m << " distance " << d << ", brute force " << in_range[m];
        return why.str();
      }
    }
  }
  if (table.pairs != pairs)
    return "pairs " + std::to_string(table.pairs) + " vs " + std::to_string(pairs);
  if (table.matched != matched)
    return "matched " + std::to_string(table.matched) + " vs " + std::to_string(matched);
  return "";
}

}  // namespace core_test
