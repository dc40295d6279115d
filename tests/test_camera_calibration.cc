// `cellmetry calibrate-camera` (camera_calibration.h): a known camera with distortion recovered
// from rendered checkerboard views within its sigmas; OpenCV's calibration sample photographs
// (opencv-doc) against OpenCV's own calibration of them; the camera file read back; the command
// line, and its refusals.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/image.h"
#include "cellmetry/imaging/camera_calibration.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/model/camera_file.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

const char kBoard[] = "{type: checkerboard, corners_x: 9, corners_y: 6, square_mm: 20}";
const char kDocData[] = "/usr/share/doc/opencv-doc/examples/data/";

std::unique_ptr<Detector> Make(const std::string& yaml) {
  const ConfigNode config = ConfigNode::LoadString(yaml, "test.yaml");
  return testing::Plugins().CreateDetector(config["type"].AsString(), config);
}

Eigen::Matrix3d Rot(const Eigen::Vector3d& axis, double degrees) {
  return Eigen::AngleAxisd(degrees * M_PI / 180.0, axis.normalized()).toRotationMatrix();
}

// The OAK-D-like camera with a barrel lens.
PinholeCamera DistortedCamera() {
  PinholeCamera camera = OakDLikeCamera();
  camera.fx = 885.0;
  camera.fy = 880.0;
  camera.cx = 645.0;
  camera.cy = 395.0;
  camera.distortion = {-0.12, 0.08, 0.0005, -0.0003, 0.0};
  return camera;
}

// 15 views of the board (its centre 320..480 mm away, tilted 0..40 degrees in different
// directions and turned), rendered into `dir`; returns the paths.
std::vector<std::string> RenderViews(const Detector& board, const PinholeCamera& camera,
                                     const std::string& dir) {
  const std::vector<MarkerFace> faces = board.Faces(10.0);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : board.layout()) centre += p.p_target_mm / board.layout().size();
  std::mt19937 rng(7);
  std::vector<std::string> paths;
  for (int i = 0; i < 15; ++i) {
    const double turn = 24.0 * i;
    const Eigen::Vector3d tilt_axis(std::cos(turn * M_PI / 180), std::sin(turn * M_PI / 180), 0);
    const double tilt = i == 0 ? 0.0 : 15.0 + 25.0 * (i % 3) / 2.0;
    Pose T_cam_target;
    T_cam_target.R = Rot(tilt_axis, tilt) * Rot(Eigen::Vector3d::UnitZ(), 10.0 * (i % 4)) *
                     Rot(Eigen::Vector3d::UnitX(), 180) * faces[0].T_target_face.R.transpose();
    // Spread over the frame, where the distortion shows.
    const Eigen::Vector3d at(60.0 * std::cos(0.9 * i), 40.0 * std::sin(1.3 * i),
                             320.0 + 160.0 * (i % 5) / 4.0);
    T_cam_target.t = at - T_cam_target.R * centre;
    const GrayImage image = RenderView(camera, {{T_cam_target, &faces}}, RenderOptions(), rng);
    char name[32];
    std::snprintf(name, sizeof(name), "/view%02d.png", i);
    WriteGrayImage(image, dir + name);
    paths.push_back(dir + name);
  }
  return paths;
}

TEST(CameraCalibration, RecoversARenderedCameraWithinItsSigmas) {
  const std::string dir = testing::TempDirForThisTest("calibrate_camera");
  const PinholeCamera truth = DistortedCamera();
  const auto board = Make(kBoard);
  const std::vector<std::string> paths = RenderViews(*board, truth, dir);
  CameraCalibrationOptions options;
  options.fix_k3 = true;  // the truth's k3 is 0; 15 views do not pin it down
  const CameraCalibration c = CalibrateCamera(*board, paths, options);
  ASSERT_EQ(c.views.size(), 15u);
  EXPECT_TRUE(c.skipped.empty());
  const std::array<double, 9> fitted = IntrinsicValues(c.camera);
  const std::array<double, 9> expected = IntrinsicValues(truth);
  std::printf("[ calib ] rendered, 15 views: RMS %.4f px\n", c.rms_px);
  for (int i = 0; i < 9; ++i) {
    std::printf("[ calib ]   %-3s %10.5f truth %10.5f sigma %.2e (%+.1f sigma)\n",
                IntrinsicNames()[i], fitted[i], expected[i], c.sigma[i],
                c.sigma[i] > 0 ? (fitted[i] - expected[i]) / c.sigma[i] : 0.0);
    if (i == 8) {
      EXPECT_EQ(fitted[i], 0.0);  // held
      continue;
    }
    EXPECT_GT(c.sigma[i], 0.0) << IntrinsicNames()[i];
    // Within 4 sigma (the sigmas hold no model error) and close in absolute terms.
    EXPECT_LT(std::abs(fitted[i] - expected[i]), 4.0 * c.sigma[i] + 1e-12) << IntrinsicNames()[i];
  }
  EXPECT_LT(std::abs(c.camera.fx - truth.fx), 1.0);
  EXPECT_LT(std::abs(c.camera.cx - truth.cx), 1.0);
  EXPECT_LT(c.rms_px, 0.1);
  for (const CalibrationView& v : c.views) EXPECT_LT(v.rms_px, 0.1) << v.path;
}

// OpenCV's calibration sample's 13 left views (9 x 6, 25 mm), as OpenCV's sample calibrated them
// (left_intrinsics.yml: aspect ratio held, fx = fy = 535.9 px, cx 342.3, cy 235.6, 0.39 px); the
// camera file written and read back.
TEST(CameraCalibration, OpenCvSamplePhotographs) {
  const std::string intrinsics = std::string(kDocData) + "left_intrinsics.yml";
  if (!std::filesystem::exists(intrinsics)) GTEST_SKIP() << intrinsics << " is not installed";
  std::vector<std::string> paths;
  for (int i = 1; i <= 14; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "left%02d.jpg", i);
    if (std::filesystem::exists(std::string(kDocData) + name)) {
      paths.push_back(std::string(kDocData) + name);
    }
  }
  // The board as configs/boards/ gives it.
  const ConfigNode config = ConfigNode::LoadFile(
      testing::Source("configs/boards/checkerboard_9x6_25mm.yaml"))["detector"];
  const auto board = testing::Plugins().CreateDetector(config["type"].AsString(), config);
  CameraCalibrationOptions options;
  options.fix_aspect_ratio = true;
  const CameraCalibration c = CalibrateCamera(*board, paths, options);
  ASSERT_EQ(c.views.size(), 13u);
  const PinholeCamera opencv = ReadCamera(intrinsics);
  std::printf(
      "[ calib ] left01..14.jpg: RMS %.3f px, fx %.2f +- %.2f, cx %.2f +- %.2f, cy %.2f +- %.2f "
      "(OpenCV's sample: fx %.2f cx %.2f cy %.2f)\n",
      c.rms_px, c.camera.fx, c.sigma[0], c.camera.cx, c.sigma[2], c.camera.cy, c.sigma[3],
      opencv.fx, opencv.cx, opencv.cy);
  EXPECT_LT(c.rms_px, 0.393);
  EXPECT_NEAR(c.camera.fx, opencv.fx, 0.01 * opencv.fx);
  EXPECT_NEAR(c.camera.cx, opencv.cx, 5.0);
  EXPECT_NEAR(c.camera.cy, opencv.cy, 5.0);
  EXPECT_DOUBLE_EQ(c.camera.fx, c.camera.fy);
  for (int i = 0; i < 9; ++i) EXPECT_TRUE(std::isfinite(c.sigma[i])) << IntrinsicNames()[i];
  EXPECT_GT(c.sigma[0], 0.0);
  EXPECT_LT(c.sigma[0], 5.0);
  // The file: the camera reads back; the figures are comments.
  const std::string path = testing::TempDirForThisTest("calibrate_camera_photos") + "/left.yaml";
  AtomicWriteFile(path, CameraFileText(c));
  const PinholeCamera read = ReadCamera(path);
  EXPECT_NEAR(read.fx, c.camera.fx, 1e-6);
  EXPECT_NEAR(read.cy, c.camera.cy, 1e-6);
  EXPECT_NEAR(read.distortion[0], c.camera.distortion[0], 1e-9);
  EXPECT_EQ(read.width, 640);
  EXPECT_EQ(read.height, 480);
}

// `left*.jpg` in OpenCV's sample folder also matches left.jpg, a 612 x 459 photograph that is
// not of the board: it is left out for showing no board, and the 640 x 480 views are used.
TEST(CameraCalibration, AFirstImageWithoutTheBoardDoesNotSetTheSize) {
  const std::string photo = std::string(kDocData) + "left.jpg";
  if (!std::filesystem::exists(photo)) GTEST_SKIP() << photo << " is not installed";
  std::vector<std::string> paths = {photo};
  for (int i = 1; i <= 4; ++i) {
    paths.push_back(std::string(kDocData) + "left0" + std::to_string(i) + ".jpg");
  }
  const ConfigNode config = ConfigNode::LoadFile(
      testing::Source("configs/boards/checkerboard_9x6_25mm.yaml"))["detector"];
  const auto board = testing::Plugins().CreateDetector(config["type"].AsString(), config);
  const CameraCalibration c = CalibrateCamera(*board, paths, CameraCalibrationOptions());
  EXPECT_EQ(c.views.size(), 4u);
  ASSERT_EQ(c.skipped.size(), 1u);
  EXPECT_EQ(c.skipped[0].first, photo);
  EXPECT_EQ(c.camera.width, 640);
}

TEST(CameraCalibrationCli, WritesTheCameraFileAndRefusesBadInput) {
  const std::string dir = testing::TempDirForThisTest("calibrate_camera_cli");
  const auto board = Make(kBoard);
  const std::vector<std::string> paths = RenderViews(*board, DistortedCamera(), dir);
  AtomicWriteFile(dir + "/board.yaml", std::string("detector: ") + kBoard + "\n");
  std::string images;
  for (const std::string& p : paths) images += " " + p;
  const auto ok = testing::RunCellmetry("calibrate-camera " + dir + "/board.yaml" + images +
                                        " -o " + dir + "/camera.yaml --fix-k3");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_THAT(ok.output, HasSubstr("Camera calibration from 15 of 15 images"));
  EXPECT_THAT(ok.output, HasSubstr("view07.png: 54 keypoints"));
  EXPECT_NEAR(ReadCamera(dir + "/camera.yaml").fx, 885.0, 1.0);

  // Run again over its own file: replaced, the earlier one kept. A camera file of the user's is
  // refused before the work, and kept; with --overwrite it is replaced and kept as .previous.
  const std::string again = "calibrate-camera " + dir + "/board.yaml " + paths[0] + " " + paths[1] +
                            " " + paths[2] + " " + paths[3] + " -o ";
  ASSERT_EQ(testing::RunCellmetry(again + dir + "/camera.yaml --fix-k3").exit_code, 0);
  EXPECT_NEAR(ReadCamera(dir + "/camera.yaml.previous").fx, 885.0, 1.0);  // the 15 views
  const std::string mine = "# my camera, measured by hand\nwidth: 1280\n";
  AtomicWriteFile(dir + "/mine.yaml", mine);
  const auto refused = testing::RunCellmetry(again + dir + "/mine.yaml");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("--overwrite"));
  EXPECT_THAT(refused.output, ::testing::Not(HasSubstr("Camera calibration from")));
  EXPECT_EQ(testing::ReadText(dir + "/mine.yaml"), mine);
  ASSERT_EQ(testing::RunCellmetry(again + dir + "/mine.yaml --overwrite").exit_code, 0);
  EXPECT_EQ(testing::ReadText(dir + "/mine.yaml.previous"), mine);
  // A camera file an earlier calibrate-camera wrote, without the export marker, is its own.
  const std::string earlier = "# cellmetry calibrate-camera: 13 views, reprojection RMS 0.2 px\n";
  AtomicWriteFile(dir + "/earlier.yaml", earlier);
  ASSERT_EQ(testing::RunCellmetry(again + dir + "/earlier.yaml").exit_code, 0);
  EXPECT_EQ(testing::ReadText(dir + "/earlier.yaml.previous"), earlier);

  // Two views are too few; a blank image is left out with the detector's reason.
  const GrayImage blank(1280, 800, 128);
  WriteGrayImage(blank, dir + "/blank.png");
  const auto few =
      testing::RunCellmetry("calibrate-camera " + dir + "/board.yaml " + paths[0] + " " + paths[1] +
                            " " + dir + "/blank.png -o " + dir + "/few.yaml");
  testing::ExpectOneLineError(few, "board.yaml:1:11:", "found the board in 2 of 3 images");
  EXPECT_FALSE(std::filesystem::exists(dir + "/few.yaml"));

  // A board that is not flat.
  AtomicWriteFile(dir + "/cube.yaml",
                  "detector: {type: apriltag_board, tag_size_mm: 20, cube_mm: 60, "
                  "cube_faces: {+x: 0, +y: 1}}\n");
  const auto cube = testing::RunCellmetry("calibrate-camera " + dir + "/cube.yaml" + images +
                                          " -o " + dir + "/cube_camera.yaml");
  testing::ExpectOneLineError(cube, "cube.yaml:1:11:", "needs a flat board");
}

}  // namespace
}  // namespace cellmetry
