// The hand-eye comparison (experiments/include/cellmetry/experiments/hand_eye_compare.h): OpenCV's
// methods fed in cellmetry's frame names recover an exact hand-eye frame in both setups (those
// this OpenCV implements soundly), and on the bundled eye-to-hand cell cellmetry's fit is more
// accurate than every OpenCV method, and on the eye-in-hand cell more accurate in position.
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/experiments/hand_eye_compare.h"
#include "opencv_hand_eye.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

Pose RandomPose(std::mt19937& rng, double turn_rad, double reach_mm) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
  return PoseFromRvecT(axis * turn_rad * std::abs(unit(rng)),
                       reach_mm * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
}

// Noise-free captures of a cell with hand-eye frame X and the other fixed frame Y.
HandEyeCaptures ExactCaptures(bool eye_in_hand, const Pose& X, const Pose& Y) {
  std::mt19937 rng(5);
  HandEyeCaptures captures;
  captures.eye_in_hand = eye_in_hand;
  for (int i = 0; i < 20; ++i) {
    const Pose T_base_flange = RandomPose(rng, 1.5, 400.0);
    captures.T_base_flange.push_back(T_base_flange);
    // Eye-in-hand: X = T_flange_cam, Y = T_base_board. Eye-to-hand: X = T_base_cam,
    // Y = T_flange_board.
    captures.T_cam_board.push_back(eye_in_hand ? (T_base_flange * X).inverse() * Y
                                               : X.inverse() * T_base_flange * Y);
  }
  return captures;
}

void ExpectEveryMethodRecovers(bool eye_in_hand, const Pose& X) {
  const Pose Y = PoseFromRvecT(Eigen::Vector3d(0.2, -0.4, 0.1), Eigen::Vector3d(30, -20, 90));
  const HandEyeCaptures captures = ExactCaptures(eye_in_hand, X, Y);
  for (const std::string& method : OpenCvHandEyeMethods()) {
    if (!OpenCvHandEyeFault(method).empty()) continue;  // said in the table
    const Pose found = OpenCvHandEye(method, captures);
    EXPECT_LT((found.t - X.t).norm(), 1e-6) << method;
    EXPECT_LT(RvecFromRotation(found.R * X.R.transpose()).norm(), 1e-9) << method;
  }
}

TEST(OpenCvHandEye, EveryMethodRecoversAnExactEyeInHandFrame) {
  ExpectEveryMethodRecovers(
      true, PoseFromRvecT(Eigen::Vector3d(0.3, 0.1, -0.5), Eigen::Vector3d(40, 10, 60)));
}

TEST(OpenCvHandEye, EveryMethodRecoversAnExactEyeToHandFrame) {
  ExpectEveryMethodRecovers(
      false, PoseFromRvecT(Eigen::Vector3d(0.3, 0.1, -0.5), Eigen::Vector3d(200, -350, 1400)));
}

TEST(OpenCvHandEye, ACameraLookingDownAtTheRobot) {
  ExpectEveryMethodRecovers(false, PoseFromRvecT(Eigen::Vector3d(-2.7435, -0.7031, 0.5422),
                                                 Eigen::Vector3d(217, -358, 1444)));
}

double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return sum / v.size();
}

// The compare's rows on `config` over `seeds` seeds, checked for shape.
std::vector<HandEyeCompareRow> CompareRows(const std::string& config, int seeds,
                                           HandEyeSetup setup) {
  HandEyeCompareSpec spec = LoadHandEyeCompare(testing::Source(config), testing::Plugins());
  EXPECT_EQ(spec.setup, setup);
  spec.seeds = seeds;
  const std::vector<HandEyeCompareRow> rows = RunHandEyeCompare(spec);
  EXPECT_EQ(rows.size(), 1 + OpenCvHandEyeMethods().size());
  EXPECT_EQ(rows[0].method, "cellmetry");
  EXPECT_EQ(rows[0].position_error_mm.size(), static_cast<size_t>(seeds));
  for (const auto& row : rows) {
    EXPECT_EQ(row.position_error_mm.size() + row.failed, static_cast<size_t>(seeds)) << row.method;
  }
  return rows;
}

TEST(HandEyeCompare, CellmetryIsMoreAccurateThanEveryOpenCvMethodOnTheEyeToHandCell) {
  const auto rows =
      CompareRows("configs/compare/hand_eye_eye_to_hand.yaml", 3, HandEyeSetup::kEyeToHand);
  for (size_t m = 1; m < rows.size(); ++m) {
    if (rows[m].position_error_mm.empty()) continue;
    EXPECT_LT(Mean(rows[0].position_error_mm), Mean(rows[m].position_error_mm)) << rows[m].method;
    EXPECT_LT(Mean(rows[0].rotation_error_mrad), Mean(rows[m].rotation_error_mrad))
        << rows[m].method;
  }
  EXPECT_LT(Mean(rows[0].position_error_mm), 0.5);
}

// Eye-in-hand, 60 captures of a board from a camera on the flange: every OpenCV method gives an
// answer, and cellmetry's weighted fit is the most accurate in position.
TEST(HandEyeCompare, CellmetryIsMoreAccurateThanEveryOpenCvMethodOnTheEyeInHandCell) {
  const auto rows =
      CompareRows("configs/compare/hand_eye_eye_in_hand.yaml", 4, HandEyeSetup::kEyeInHand);
  for (size_t m = 1; m < rows.size(); ++m) {
    EXPECT_EQ(rows[m].failed, 0) << rows[m].method;
    EXPECT_LT(Mean(rows[0].position_error_mm), Mean(rows[m].position_error_mm)) << rows[m].method;
  }
  EXPECT_LT(Mean(rows[0].position_error_mm), 0.2);
}

}  // namespace
}  // namespace cellmetry
