// run_settings.cpp - the canonical settings of a run.
#include "bench/run_settings.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "bench/results_csv.hpp"
#include "ppcr/version.hpp"

namespace ppcr_bench {
namespace {

// A value that is a number in its shortest exact form, anything else as typed.
std::string canonical(const std::string& value) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  return value.empty() || *end != '\0' ? value : round_trip(x);
}

// FNV-1a, 64 bits: equal problem lists give equal digests on every host.
struct Digest {
  std::uint64_t h = 14695981039346656037ull;
  void add(const std::string& text) {
    for (unsigned char c : text + '\n') h = (h ^ c) * 1099511628211ull;
  }
  std::string hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
    return text;
  }
};

}  // namespace

std::string flag_name(const CLI::Option& o) {
  if (!o.get_lnames().empty()) return "--" + o.get_lnames().front();
  return o.get_name(true);
}

bool is_local_flag(const std::string& name) {
  static const char* const kLocal[] = {"PROBLEMS", "--data-root", "--out",   "--trace-dir",
                                       "--quiet",  "--json",      "--shard", "--merge",
                                       "--help",   "--version"};
  return std::find(std::begin(kLocal), std::end(kLocal), name) != std::end(kLocal);
}

std::string run_settings(const CLI::App& app, const std::vector<Problem>& problems) {
  std::vector<std::string> flags;
  for (const CLI::Option* o : app.get_options()) {
    const std::string name = flag_name(*o);
    if (o->count() == 0 || is_local_flag(name)) continue;
    std::string values;
    for (const std::string& v : o->results()) values += (values.empty() ? "" : ",") + canonical(v);
    flags.push_back(name + "=" + values);
  }
  std::sort(flags.begin(), flags.end());
  Digest digest;
  for (const Problem& p : problems) {
    digest.add(p.id + ' ' + p.source + ' ' + p.target);
    for (int k = 0; k < 12; ++k) digest.add(round_trip(p.T0.matrix()(k / 4, k % 4)));
  }
  std::string text;
  for (const std::string& f : flags) text += f + ' ';
  return text + "problems=" + digest.hex() + " version=" + PPCR_VERSION_STRING;
}

}  // namespace ppcr_bench
