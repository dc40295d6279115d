// Camera calibration files (model/camera_file.h, imaging/stereo.h): a ROS camera_info file reads
// as the same camera as OpenCV's FileStorage file of the same calibration; a ROS stereo pair's
// extrinsics come back from its rectification and projection matrices as OpenCV's stereoRectify
// made them; what cellmetry cannot model is refused at its line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <sstream>

#include "cellmetry/basics/error.h"
#include "cellmetry/imaging/stereo.h"
#include "cellmetry/model/camera_file.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

std::string RosMatrix(const std::string& name, int rows, int cols, const double* data) {
  std::ostringstream out;
  out.precision(17);
  out << name << ":\n  rows: " << rows << "\n  cols: " << cols << "\n  data: [";
  for (int i = 0; i < rows * cols; ++i) out << (i ? ", " : "") << data[i];
  out << "]\n";
  return out.str();
}

// A camera_info file as camera_calibration writes it.
std::string RosCameraInfoYaml(const cv::Mat& K, const cv::Mat& D, const cv::Mat& R,
                              const cv::Mat& P, const std::string& model = "plumb_bob") {
  return "image_width: 1280\nimage_height: 800\ncamera_name: narrow_stereo/left\n" +
         RosMatrix("camera_matrix", 3, 3, K.ptr<double>()) + "distortion_model: " + model + "\n" +
         RosMatrix("distortion_coefficients", 1, static_cast<int>(D.total()), D.ptr<double>()) +
         RosMatrix("rectification_matrix", 3, 3, R.ptr<double>()) +
         RosMatrix("projection_matrix", 3, 4, P.ptr<double>());
}

cv::Mat CameraMatrix(double f, double cx, double cy) {
  return (cv::Mat_<double>(3, 3) << f, 0, cx, 0, 1.01 * f, cy, 0, 0, 1);
}

TEST(CameraFiles, RosCameraInfoIsTheSameCameraAsOpenCvsFile) {
  const std::string dir = testing::TempDirForThisTest("camera_files");
  const cv::Mat K = CameraMatrix(880.5, 641.2, 398.7);
  const cv::Mat D = (cv::Mat_<double>(1, 5) << -0.21, 0.08, 1e-3, -5e-4, -0.01);
  cv::FileStorage fs(dir + "/opencv.yaml", cv::FileStorage::WRITE);
  fs << "image_width" << 1280 << "image_height" << 800 << "camera_matrix" << K
     << "distortion_coefficients" << D;
  fs.release();
  const cv::Mat I = cv::Mat::eye(3, 3, CV_64F), P = cv::Mat::zeros(3, 4, CV_64F);
  testing::WriteText(dir + "/ros.yaml", RosCameraInfoYaml(K, D, I, P));
  const PinholeCamera ros = ReadCamera(dir + "/ros.yaml");
  const PinholeCamera opencv = ReadCamera(dir + "/opencv.yaml");
  EXPECT_EQ(ros.width, 1280);
  EXPECT_EQ(ros.height, 800);
  EXPECT_DOUBLE_EQ(ros.fx, 880.5);
  EXPECT_DOUBLE_EQ(ros.fy, 1.01 * 880.5);
  EXPECT_DOUBLE_EQ(ros.cx, opencv.cx);
  EXPECT_DOUBLE_EQ(ros.cy, opencv.cy);
  for (int i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(ros.distortion[i], opencv.distortion[i]) << i;
  const Eigen::Vector3d p(120, -45, 900);
  EXPECT_LT((ros.Project(p) - opencv.Project(p)).norm(), 1e-12);
}

// A rig with a known pose, rectified by OpenCV as ROS's camera_calibration does, written as two
// camera_info files with the baseline in metres: the rig read back has the same extrinsics.
TEST(CameraFiles, RosStereoPairGivesTheRigsExtrinsics) {
  const std::string dir = testing::TempDirForThisTest("camera_files");
  const cv::Mat K1 = CameraMatrix(880, 640, 400), K2 = CameraMatrix(870, 630, 405);
  const cv::Mat D1 = (cv::Mat_<double>(1, 5) << -0.1, 0.02, 0, 0, 0);
  const cv::Mat D2 = cv::Mat::zeros(1, 5, CV_64F);
  const Eigen::Vector3d rvec(0.01, -0.03, 0.005);
  const Eigen::Vector3d t_mm(-75.2, 0.8, -1.1);  // p_right = R p_left + t
  const Pose truth = PoseFromRvecT(rvec, t_mm);
  cv::Mat R(3, 3, CV_64F), T(3, 1, CV_64F);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) R.at<double>(i, k) = truth.R(i, k);
    T.at<double>(i) = t_mm[i] / 1000.0;  // ROS calibrations measure in metres
  }
  cv::Mat R1, R2, P1, P2, Q;
  cv::stereoRectify(K1, D1, K2, D2, cv::Size(1280, 800), R, T, R1, R2, P1, P2, Q);
  testing::WriteText(dir + "/left.yaml", RosCameraInfoYaml(K1, D1, R1, P1));
  testing::WriteText(dir + "/right.yaml", RosCameraInfoYaml(K2, D2, R2, P2));
  testing::WriteText(dir + "/rig.yaml",
                     "stereo: {left: left.yaml, right: right.yaml, units: {length: m}}\n");
  const StereoRig rig = ReadStereoRig(dir + "/rig.yaml");
  EXPECT_LT((rig.T_right_left.t - t_mm).norm(), 1e-9);
  EXPECT_LT((rig.T_right_left.R - truth.R).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(rig.right.fx, 870);
  EXPECT_DOUBLE_EQ(rig.left.distortion[0], -0.1);

  testing::WriteText(dir + "/no_units.yaml", "stereo: {left: left.yaml, right: right.yaml}\n");
  try {
    ReadStereoRig(dir + "/no_units.yaml");
    FAIL() << "a ROS baseline without its unit was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no_units.yaml:1:"));
    EXPECT_THAT(e.what(), HasSubstr("units: {length: m}"));
  }
}

TEST(CameraFiles, WhatCellmetryCannotModelIsRefusedAtItsLine) {
  const std::string dir = testing::TempDirForThisTest("camera_files");
  const cv::Mat K = CameraMatrix(880, 640, 400), I = cv::Mat::eye(3, 3, CV_64F);
  const cv::Mat P = cv::Mat::zeros(3, 4, CV_64F);
  const cv::Mat D4 = (cv::Mat_<double>(1, 4) << 0.1, 0.01, 0, 0);
  const cv::Mat D8 = (cv::Mat_<double>(1, 8) << 0.1, 0.01, 0, 0, 0, 0.3, 0, 0);
  struct Case {
    std::string yaml, message;
  } cases[] = {
      {RosCameraInfoYaml(K, D4, I, P, "equidistant"), "ros.yaml:8:19: error: distortion_model"},
      {RosCameraInfoYaml(K, D8, I, P, "rational_polynomial"), "coefficient k4 is not zero"},
      {testing::ReplaceOnce(RosCameraInfoYaml(K, D4, I, P), "camera_matrix:\n  rows: 3\n  cols: 3",
                            "camera_matrix:\n  rows: 3\n  cols: 2"),
       "camera_matrix"},
      {testing::ReplaceOnce(RosCameraInfoYaml(K, D4, I, P), "image_height: 800\n", ""),
       "missing field 'image_height'"},
  };
  for (const Case& c : cases) {
    testing::WriteText(dir + "/ros.yaml", c.yaml);
    try {
      ReadCamera(dir + "/ros.yaml");
      ADD_FAILURE() << "accepted:\n" << c.yaml;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(c.message)) << c.yaml;
    }
  }
}

// OpenCV's own reader asserts on some of these (a matrix whose data does not fill rows x cols);
// each must be an InputError naming the field, never OpenCV's exception.
TEST(CameraFiles, AMalformedOpenCvFileIsRefusedNamingTheField) {
  const std::string dir = testing::TempDirForThisTest("camera_files");
  const std::string good =
      "%YAML:1.0\n---\nimage_width: 1280\nimage_height: 800\n"
      "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
      "   data: [ 881.5, 0., 641.2, 0., 880.25, 398.7, 0., 0., 1. ]\n"
      "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
      "   data: [ -0.21, 0.06, 0.0012, -0.0007, -0.01 ]\n";
  testing::WriteText(dir + "/opencv.yml", good);
  EXPECT_EQ(ReadCamera(dir + "/opencv.yml").width, 1280);
  struct Case {
    std::string from, to, message;
  } cases[] = {
      {"rows: 5", "rows: 2", "'distortion_coefficients' does not hold rows x cols = 2 numbers"},
      {"rows: 3", "rows: 3000000000", "'camera_matrix' has no rows from 1 to 16"},
      {"cols: 3", "cols:)3", "'camera_matrix' has no cols"},
      {"880.25", ".nan", "'camera_matrix' holds a number that is not finite"},
      {"   dt: d\n   data: [ 881.5", "   dt: \"2d\"\n   data: [ 881.5", "'camera_matrix' is not"},
      {"image_width: 1280", "image_width: 1e300", "'image_width' is not a whole number of pixels"},
      {"image_height: 800", "image_height: 800.5", "'image_height' is not a whole number"},
      {"image_width: 1280", "image_width: wide", "'image_width' is not a whole number"},
      {"camera_matrix: !!opencv-matrix", "camera_matrix: 3\nunused: !!opencv-matrix",
       "'camera_matrix' has no rows"},
      {"880.25", "-880.25", "focal lengths must be positive"},
  };
  for (const Case& c : cases) {
    const std::string text = testing::ReplaceOnce(good, c.from, c.to);
    testing::WriteText(dir + "/opencv.yml", text);
    try {
      ReadCamera(dir + "/opencv.yml");
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("opencv.yml")) << text;
      EXPECT_THAT(e.what(), HasSubstr(c.message)) << text;
    }
  }
  // A key that starts with its colon made OpenCV's parser throw std::length_error.
  testing::WriteText(dir + "/opencv.yml", testing::ReplaceOnce(good, "cols: 1", ":ocls 1"));
  EXPECT_THAT(testing::CatchInputError([&] { ReadCamera(dir + "/opencv.yml"); }).what(),
              HasSubstr("not a readable OpenCV calibration file"));
  testing::WriteText(dir + "/opencv.yml", "%YAML:1.0\n---\n- 1\n- 2\n");
  EXPECT_THAT(testing::CatchInputError([&] { ReadCamera(dir + "/opencv.yml"); }).what(),
              HasSubstr("not an OpenCV calibration file"));
}

}  // namespace
}  // namespace cellmetry
