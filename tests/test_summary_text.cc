// The terminal summary stays short: of the strongly correlated pairs it lists the five strongest
// and counts the rest, which result.json and the report list whole.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cellmetry/cell/result_io.h"

namespace cellmetry {
namespace {

TEST(Summary, ListsTheFiveStrongestCorrelationsAndCountsTheRest) {
  WorkcellResult result;
  for (int k = 0; k < 8; ++k) {
    result.strong_correlations.push_back(
        {"a" + std::to_string(k), "b" + std::to_string(k), 0.99 - 0.01 * k});
  }
  const std::string summary = WorkcellSummary(result);
  EXPECT_THAT(summary, ::testing::HasSubstr("strongly correlated: a4 ~ b4 (0.950)"));
  EXPECT_THAT(summary, ::testing::Not(::testing::HasSubstr("a5 ~ b5")));
  EXPECT_THAT(summary,
              ::testing::HasSubstr("strongly correlated: 3 more pairs (result.json, report.html)"));
  EXPECT_THAT(WorkcellResultJson(result).dump(), ::testing::HasSubstr("a7"));
}

}  // namespace
}  // namespace cellmetry
