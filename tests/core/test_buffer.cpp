// Tests of buffer.hpp: a Buffer holds what a std::vector holds through growth, copies and
// shrinking, and values given explicitly are written.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "common/buffer.hpp"

using ppcr::detail::Buffer;

TEST_CASE("Buffer holds what a vector holds", "[buffer]") {
  Buffer<double> b;
  std::vector<double> v;
  for (std::size_t n : {0, 1, 1000, 300000, 7}) {
    INFO("n " << n);
    b.resize(n);
    v.resize(n);
    for (std::size_t i = 0; i < n; ++i) b[i] = v[i] = static_cast<double>(i * 3 + 1);
    REQUIRE(b.size() == n);
    CHECK(std::equal(b.begin(), b.end(), v.begin()));
  }
  // Growth keeps the elements held; shrinking keeps the first ones.
  Buffer<std::uint32_t> c(5, 7u);
  CHECK(c == Buffer<std::uint32_t>{7u, 7u, 7u, 7u, 7u});
  c.resize(1u << 20);
  for (std::size_t i = 0; i < 5; ++i) CHECK(c[i] == 7u);
  c.resize(3);
  c.shrink_to_fit();
  CHECK(c == Buffer<std::uint32_t>{7u, 7u, 7u});
  // Values given explicitly are written (only construction without arguments leaves them).
  Buffer<double> d(100000, -1.0);
  CHECK(std::all_of(d.begin(), d.end(), [](double x) { return x == -1.0; }));
  d.resize(200000, 2.0);
  CHECK(std::all_of(d.begin() + 100000, d.end(), [](double x) { return x == 2.0; }));
  const Buffer<double> copy = d;
  CHECK(copy == d);
}
