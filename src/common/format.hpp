// format.hpp - numbers in the core's messages.
#pragma once

#include <sstream>
#include <string>

namespace ppcr {
namespace detail {

/// A value with 6 significant digits, as messages quote it.
inline std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace detail
}  // namespace ppcr
