// shard.cpp - the --shard I/N value.
#include "bench/shard.hpp"

#include <cerrno>
#include <cstdlib>

namespace ppcr_bench {
namespace {

// A whole decimal number, digits only (no sign, no blanks), that fits a size_t.
bool read_count(const std::string& text, std::size_t* value) {
  if (text.empty() || text.size() > 9 ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    return false;
  }
  *value = static_cast<std::size_t>(std::strtoul(text.c_str(), nullptr, 10));
  return true;
}

}  // namespace

ppcr::Status parse_shard(const std::string& text, Shard* shard) {
  const std::string flag = "--shard " + text + ": ";
  const std::size_t slash = text.find('/');
  Shard s;
  if (slash == std::string::npos || !read_count(text.substr(0, slash), &s.index) ||
      !read_count(text.substr(slash + 1), &s.count)) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument,
                        flag + "expected I/N, two whole numbers (e.g. 0/4: the first of 4 shards)");
  }
  if (s.count == 0) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument, flag + "N must be at least 1");
  }
  if (s.index >= s.count) {
    return ppcr::Status(ppcr::StatusCode::kInvalidArgument, flag + "I must be in [0, N)");
  }
  *shard = s;
  return ppcr::Status::Ok();
}

}  // namespace ppcr_bench
