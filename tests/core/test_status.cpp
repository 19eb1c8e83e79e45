// Tests of ppcr::Status and the stable names of the core's enums (used in logs and JSON).
#include <catch2/catch.hpp>
#include <set>
#include <string>

#include "ppcr/status.hpp"
#include "registration/termination.hpp"
#include "solver/lm_options.hpp"

TEST_CASE("Status: default and Ok() are ok, with an empty message", "[status]") {
  const ppcr::Status a;
  CHECK(a.ok());
  CHECK(a.code() == ppcr::StatusCode::kOk);
  CHECK(a.message().empty());
  CHECK(a.to_string() == "ok");
  CHECK(ppcr::Status::Ok().ok());
}

TEST_CASE("Status: code, message and to_string", "[status]") {
  const ppcr::Status s(ppcr::StatusCode::kEmptyCloud, "source has 2 usable point(s)");
  CHECK_FALSE(s.ok());
  CHECK(s.code() == ppcr::StatusCode::kEmptyCloud);
  CHECK(s.message() == "source has 2 usable point(s)");
  CHECK(s.to_string() == "empty_cloud: source has 2 usable point(s)");
}

TEST_CASE("StatusCode names are the documented stable strings", "[status]") {
  CHECK(std::string(ppcr::to_string(ppcr::StatusCode::kOk)) == "ok");
  CHECK(std::string(ppcr::to_string(ppcr::StatusCode::kInvalidArgument)) == "invalid_argument");
  CHECK(std::string(ppcr::to_string(ppcr::StatusCode::kEmptyCloud)) == "empty_cloud");
  CHECK(std::string(ppcr::to_string(ppcr::StatusCode::kNoCorrespondences)) == "no_correspondences");
  CHECK(std::string(ppcr::to_string(ppcr::StatusCode::kNumericalFailure)) == "numerical_failure");
  CHECK(std::string(ppcr::to_string(ppcr::StatusCode::kIoError)) == "io_error");
  CHECK(std::string(ppcr::to_string(ppcr::StatusCode::kParseError)) == "parse_error");
}

TEST_CASE("LMTermination and StopReason names are distinct and known", "[status]") {
  std::set<std::string> lm;
  for (ppcr::LMTermination t :
       {ppcr::LMTermination::kFunctionTolerance, ppcr::LMTermination::kGradientTolerance,
        ppcr::LMTermination::kStepTolerance, ppcr::LMTermination::kMaxIterations,
        ppcr::LMTermination::kLambdaTooLarge, ppcr::LMTermination::kNoResiduals,
        ppcr::LMTermination::kNumericalFailure}) {
    const std::string name = ppcr::to_string(t);
    CHECK(name != "unknown");
    lm.insert(name);
  }
  CHECK(lm.size() == 7u);
  std::set<std::string> stop;
  for (ppcr::StopReason r :
       {ppcr::StopReason::kNone, ppcr::StopReason::kFixedIterations, ppcr::StopReason::kCostDrop,
        ppcr::StopReason::kMsePrev, ppcr::StopReason::kSuccessfulSteps,
        ppcr::StopReason::kMaxIterations, ppcr::StopReason::kZeroCost,
        ppcr::StopReason::kNoCorrespondences, ppcr::StopReason::kNumericalFailure,
        ppcr::StopReason::kInvalidInput, ppcr::StopReason::kCancelled}) {
    const std::string name = ppcr::to_string(r);
    CHECK(name != "unknown");
    stop.insert(name);
  }
  CHECK(stop.size() == 11u);
}
