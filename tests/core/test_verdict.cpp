// The verdict's rules (verdict.hpp) against their documented statement, one rule at a time, at
// and beside each threshold, and in their documented order.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "ppcr/result.hpp"
#include "quality/verdict.hpp"

using ppcr::Quality;
using ppcr::RegistrationResult;
using ppcr::StopReason;
using ppcr::detail::judge;

namespace {

// A result no rule flags.
RegistrationResult agreeing() {
  RegistrationResult r;
  r.stop_reason = StopReason::kCostDrop;
  r.iterations = 20;
  r.fitness = 0.9;
  r.close_fraction = 0.95;
  r.degenerate_directions = 0;
  return r;
}

bool contains(const char* text, const std::string& part) {
  return std::string(text).find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("verdict: a result that agrees is good, with no reason", "[verdict]") {
  const ppcr::detail::Verdict v = judge(agreeing());
  CHECK(v.quality == Quality::kGood);
  CHECK(std::string(v.reason).empty());
  CHECK(std::string(ppcr::to_string(Quality::kGood)) == "good");
  CHECK(std::string(ppcr::to_string(Quality::kWeak)) == "weak");
  CHECK(std::string(ppcr::to_string(Quality::kFailed)) == "failed");
}

TEST_CASE("verdict: each rule at and beside its threshold", "[verdict]") {
  struct Case {
    const char* what;
    void (*change)(RegistrationResult*);
    Quality expected;
    const char* reason_part;
  };
  const Case cases[] = {
      {"a failed status",
       [](RegistrationResult* r) {
         r->status = ppcr::Status(ppcr::StatusCode::kNoCorrespondences, "none");
       },
       Quality::kFailed, "status"},
      {"fitness just below 5 %", [](RegistrationResult* r) { r->fitness = 0.0499; },
       Quality::kFailed, "fitness below 5 %"},
      {"fitness 5 %: not failed, weak (below 50 %)",
       [](RegistrationResult* r) { r->fitness = 0.05; }, Quality::kWeak, "fitness below 50 %"},
      {"fitness 50 %: good", [](RegistrationResult* r) { r->fitness = 0.5; }, Quality::kGood, ""},
      {"close fraction just below 60 %", [](RegistrationResult* r) { r->close_fraction = 0.5999; },
       Quality::kFailed, "fewer than 60 %"},
      {"close fraction 60 %: weak", [](RegistrationResult* r) { r->close_fraction = 0.6; },
       Quality::kWeak, "fewer than 75 %"},
      {"close fraction 75 %: good", [](RegistrationResult* r) { r->close_fraction = 0.75; },
       Quality::kGood, ""},
      {"free directions with a loose fit",
       [](RegistrationResult* r) {
         r->degenerate_directions = 2;
         r->close_fraction = 0.85;
       },
       Quality::kWeak, "directions free"},
      {"free directions with a tight fit: not flagged",
       [](RegistrationResult* r) {
         r->degenerate_directions = 3;
         r->close_fraction = 0.9;
       },
       Quality::kGood, ""},
      {"the point model's -1 (not assessed) is no free direction",
       [](RegistrationResult* r) {
         r->degenerate_directions = -1;
         r->close_fraction = 0.8;
       },
       Quality::kGood, ""},
      {"no spacing (NaN close fraction): the close rules are skipped",
       [](RegistrationResult* r) { r->close_fraction = std::nan(""); }, Quality::kGood, ""},
      {"the iteration cap",
       [](RegistrationResult* r) { r->stop_reason = StopReason::kMaxIterations; }, Quality::kWeak,
       "iteration cap"},
      {"cancelled", [](RegistrationResult* r) { r->stop_reason = StopReason::kCancelled; },
       Quality::kWeak, "cancelled"},
      {"failed rules come before weak ones",
       [](RegistrationResult* r) {
         r->stop_reason = StopReason::kMaxIterations;
         r->close_fraction = 0.3;
       },
       Quality::kFailed, "do not coincide"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    RegistrationResult r = agreeing();
    c.change(&r);
    const ppcr::detail::Verdict v = judge(r);
    CHECK(v.quality == c.expected);
    CHECK(contains(v.reason, c.reason_part));
  }
}
