// shard.hpp - `ppcr_bench --shard I/N`: a batch split over N processes or hosts. Problem i
// (0-based, in the order of the problem file) belongs to shard i mod N, so the shards are disjoint,
// cover every problem and take turns through the file (hard and easy problems spread evenly).
#pragma once

#include <cstddef>
#include <string>

#include "ppcr/status.hpp"

namespace ppcr_bench {

struct Shard {
  std::size_t index = 0;  // I
  std::size_t count = 1;  // N; one shard is the whole run

  bool has(std::size_t problem_index) const { return problem_index % count == index; }
};

/// Reads `I/N` (decimal, 0 <= I < N). The message names --shard and the value seen.
ppcr::Status parse_shard(const std::string& text, Shard* shard);

}  // namespace ppcr_bench
