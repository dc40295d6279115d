// The marker comparison (the report's Tables 3 and 4) on rendered stereo images.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cellmetry/experiments/marker_comparison.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

// Depth repeatability orders as the report found it: 13-dot pattern < white dot < ArUco; each
// is stated beside its Cramer-Rao floor, and no detector beats its floor by more than the
// sampling error of a 40-capture sigma.
TEST(MarkerComparison, DepthRepeatabilityOrdersPatternDotAruco) {
  MarkerComparisonSpec spec =
      LoadMarkerComparison(testing::Source("configs/compare/markers.yaml"), testing::Plugins());
  spec.captures = 40;
  spec.positions = 10;
  const std::vector<MarkerRow> rows = CompareMarkers(spec, testing::Plugins());
  ASSERT_EQ(rows.size(), 4u);
  const MarkerRow &dot = rows[0], &pattern = rows[1], &aruco = rows[2];
  EXPECT_EQ(rows[3].label, "apriltag");  // shown printed side up like the others (was 0 found)
  EXPECT_LT(pattern.repeatability_mm.z(), dot.repeatability_mm.z());
  EXPECT_LT(dot.repeatability_mm.z(), aruco.repeatability_mm.z());
  for (const auto& r : rows) {
    SCOPED_TRACE(r.label);
    EXPECT_EQ(r.captures_found, 40);
    EXPECT_GT(r.floor_mm.z(), 0.0);
    EXPECT_GT(r.repeatability_mm.z() / r.floor_mm.z(), 0.7);
    EXPECT_EQ(r.positions_found, 10);
  }
  // The dot is within 1.5x of its floor (the bar for the dot's centre).
  EXPECT_LT(dot.repeatability_mm.z() / dot.floor_mm.z(), 1.5);
  const std::string table = MarkerTableMarkdown(spec, rows);
  EXPECT_NE(table.find("depth / floor"), std::string::npos);
}

// An interrupted comparison resumes: seeds in the checkpoint are read back, not run again (a
// figure planted there comes back), and a checkpoint of another spec is not reused.
TEST(MarkerComparison, ResumesFinishedSeedsFromItsCheckpoint) {
  const std::string dir = testing::TempDirForThisTest("marker_resume");
  MarkerComparisonSpec spec =
      LoadMarkerComparison(testing::Source("configs/compare/markers.yaml"), testing::Plugins());
  spec.detectors.erase(spec.detectors.begin() + 1, spec.detectors.end());  // the dot
  spec.captures = 4;
  spec.positions = 3;
  spec.seeds = 2;
  const std::string checkpoint = dir + "/markers.partial.json";
  const auto first = CompareMarkersOverSeeds(spec, testing::Plugins(), checkpoint);
  ASSERT_EQ(first.size(), 2u);
  nlohmann::json done;
  std::ifstream(checkpoint) >> done;
  ASSERT_EQ(done.size(), 2u);
  const std::string key = spec.fingerprint + "/" + std::to_string(spec.seed + 1);
  ASSERT_TRUE(done.contains(key));
  EXPECT_DOUBLE_EQ(done[key][0]["workspace_rms_mm"].get<double>(), first[1][0].workspace_rms_mm);
  done[key][0]["workspace_rms_mm"] = 123.0;
  std::ofstream(checkpoint) << done.dump();

  const auto resumed = CompareMarkersOverSeeds(spec, testing::Plugins(), checkpoint);
  EXPECT_EQ(resumed[1][0].workspace_rms_mm, 123.0);
  EXPECT_EQ(resumed[0][0].repeatability_mm, first[0][0].repeatability_mm);

  spec.fingerprint += "-edited";
  const auto fresh = CompareMarkersOverSeeds(spec, testing::Plugins(), checkpoint);
  EXPECT_DOUBLE_EQ(fresh[1][0].workspace_rms_mm, first[1][0].workspace_rms_mm);
}

}  // namespace
}  // namespace cellmetry
