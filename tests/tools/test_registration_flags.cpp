// The registration flags of ppcr_cli and ppcr_bench (tools/common/registration_flags.hpp):
// parsed values reach RegistrationOptions, defaults are the library's, and a bad value is
// refused with a message naming the flag and the value seen.
#include <catch2/catch.hpp>
#include <string>

#include "common/registration_flags.hpp"

namespace {

struct Parsed {
  ppcr::Status status;
  ppcr::RegistrationOptions options;
};

Parsed parse(const std::string& command_line) {
  CLI::App app;
  ppcr_tools::RegistrationFlags flags;
  ppcr_tools::add_registration_flags(app, &flags);
  app.parse(command_line, false);
  Parsed p;
  p.status = ppcr_tools::to_options(flags, &p.options);
  return p;
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("no flags give the library's default options", "[tools]") {
  const Parsed p = parse("");
  REQUIRE(p.status.ok());
  const ppcr::RegistrationOptions defaults;
  CHECK(p.options.radius == defaults.radius);
  CHECK(p.options.max_neighbours == defaults.max_neighbours);
  CHECK(p.options.error_model == defaults.error_model);
  CHECK(p.options.expert.neighbour_cache == defaults.expert.neighbour_cache);
  CHECK(p.options.expert.acceleration_memory == defaults.expert.acceleration_memory);
  CHECK(p.options.expert.coarse_stride == defaults.expert.coarse_stride);
  CHECK(p.options.expert.lm_function_tolerance == defaults.expert.lm_function_tolerance);
  CHECK(p.options.expert.lm_fine_function_tolerance == defaults.expert.lm_fine_function_tolerance);
  CHECK(p.options.expert.em_min_shrink == defaults.expert.em_min_shrink);
}

TEST_CASE("the LM tolerance flags reach the LM options", "[tools]") {
  const Parsed p = parse("--lm-tolerance 0.001 --lm-fine-tolerance 0.02 --radius 0.5");
  REQUIRE(p.status.ok());
  CHECK(p.options.expert.lm_function_tolerance == 0.001);
  CHECK(p.options.expert.lm_fine_function_tolerance == 0.02);
  CHECK(p.options.radius == 0.5);
  CHECK(ppcr::validate(p.options).ok());
}

TEST_CASE("the LM fine tolerance flag takes auto (the default) or a number", "[tools]") {
  CHECK(parse("").options.expert.lm_fine_function_tolerance == ppcr::ExpertOptions::kAutomatic);
  const Parsed automatic = parse("--lm-fine-tolerance auto");
  REQUIRE(automatic.status.ok());
  CHECK(automatic.options.expert.lm_fine_function_tolerance == ppcr::ExpertOptions::kAutomatic);
  const Parsed off = parse("--lm-fine-tolerance 0 --scale raw");
  REQUIRE(off.status.ok());
  CHECK(off.options.expert.lm_fine_function_tolerance == 0.0);
}

TEST_CASE("the coarse stride flag takes auto (the default) or an integer in [1, 64]", "[tools]") {
  CHECK(parse("").options.expert.coarse_stride == ppcr::ExpertOptions::kAutomatic);
  CHECK(parse("--coarse-stride auto").options.expert.coarse_stride ==
        ppcr::ExpertOptions::kAutomatic);
  for (int stride : {1, 4, 64}) {
    const Parsed p = parse("--coarse-stride " + std::to_string(stride));
    REQUIRE(p.status.ok());
    CHECK(p.options.expert.coarse_stride == stride);
    CHECK(ppcr::validate(p.options).ok());
  }
  CHECK(parse("--coarse-stride 1 --scale raw").status.ok());  // 1 is every point: no EM needed
}

TEST_CASE("bad flag values are refused, naming the flag and the value", "[tools]") {
  struct Bad {
    const char* line;
    const char* flag;
    const char* value;
  };
  const Bad cases[] = {
      {"--lm-tolerance -1", "--lm-tolerance", "-1"},
      {"--lm-tolerance nan", "--lm-tolerance", "nan"},
      {"--lm-fine-tolerance -0.5", "--lm-fine-tolerance", "-0.5"},
      {"--lm-fine-tolerance inf", "--lm-fine-tolerance", "inf"},
      {"--lm-fine-tolerance -1", "--lm-fine-tolerance", "-1"},
      {"--lm-fine-tolerance fast", "--lm-fine-tolerance", "fast"},
      {"--lm-fine-tolerance 0.01 --scale raw", "--lm-fine-tolerance", "raw"},
      {"--scale-shrink 0", "--scale-shrink", "0"},
      {"--neighbour-cache -2", "--neighbour-cache", "-2"},
      {"--acceleration -1", "--acceleration", "-1"},
      {"--acceleration 9", "--acceleration", "9"},
      {"--coarse-stride 0", "--coarse-stride", "0"},
      {"--coarse-stride 65", "--coarse-stride", "65"},
      {"--coarse-stride 2.5", "--coarse-stride", "2.5"},
      {"--coarse-stride -1", "--coarse-stride", "-1"},
      {"--coarse-stride half", "--coarse-stride", "half"},
      {"--coarse-stride 2 --scale raw", "--coarse-stride", "raw"},
      {"--radius -1", "--radius", "-1"},
  };
  for (const Bad& b : cases) {
    const Parsed p = parse(b.line);
    INFO(b.line << " -> " << p.status.to_string());
    CHECK_FALSE(p.status.ok());
    CHECK(contains(p.status.message(), b.flag));
    CHECK(contains(p.status.message(), b.value));
  }
}
