// natural_order.cpp - natural comparison of names.
#include "odometry/natural_order.hpp"

#include <cstddef>

namespace ppcr_odometry {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Compares the digit runs starting at a[i] and b[j] by value (leading zeros skipped: longer
// significant part is larger, else the first different digit); advances i and j past them.
// Returns <0, 0 or >0; *zeros_order tells fewer leading zeros apart when the values are equal.
int compare_numbers(const std::string& a, std::size_t* i, const std::string& b, std::size_t* j,
                    int* zeros_order) {
  const std::size_t a_start = *i, b_start = *j;
  while (*i < a.size() && a[*i] == '0') ++*i;
  while (*j < b.size() && b[*j] == '0') ++*j;
  const std::size_t a_digits = *i, b_digits = *j;
  while (*i < a.size() && is_digit(a[*i])) ++*i;
  while (*j < b.size() && is_digit(b[*j])) ++*j;
  const std::size_t a_length = *i - a_digits, b_length = *j - b_digits;
  if (a_length != b_length) return a_length < b_length ? -1 : 1;
  for (std::size_t k = 0; k < a_length; ++k) {
    if (a[a_digits + k] != b[b_digits + k]) return a[a_digits + k] < b[b_digits + k] ? -1 : 1;
  }
  const std::size_t a_zeros = a_digits - a_start, b_zeros = b_digits - b_start;
  if (*zeros_order == 0 && a_zeros != b_zeros) *zeros_order = a_zeros < b_zeros ? -1 : 1;
  return 0;
}

}  // namespace

bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  int zeros_order = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      const int order = compare_numbers(a, &i, b, &j, &zeros_order);
      if (order != 0) return order < 0;
      continue;
    }
    if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
    ++i;
    ++j;
  }
  if (i < a.size() || j < b.size()) return j < b.size();  // a is a prefix of b
  if (zeros_order != 0) return zeros_order < 0;
  return a < b;
}

}  // namespace ppcr_odometry
