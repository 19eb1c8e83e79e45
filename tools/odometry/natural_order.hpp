// natural_order.hpp - file names in natural order: runs of digits compare as numbers, so that
// scan_2 < scan_10 and scan_000009 < scan_000010; other characters compare as bytes.
#pragma once

#include <string>

namespace ppcr_odometry {

/// True when a comes before b in natural order. Digit runs of equal value compare by length
/// (fewer leading zeros first), and names equal in natural order by bytes, so that the order is
/// strict and total.
bool natural_less(const std::string& a, const std::string& b);

}  // namespace ppcr_odometry
