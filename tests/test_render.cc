// Camera model, image and calibration readers, and the rendering simulator's image formation.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>

#include "cellmetry/basics/error.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/model/camera_file.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

PinholeCamera DistortedCamera() {
  PinholeCamera camera = OakDLikeCamera();
  camera.distortion = {-0.21, 0.06, 0.0012, -0.0007, -0.01};
  return camera;
}

TEST(PinholeCamera, RayInvertsProjectionWithDistortion) {
  const PinholeCamera camera = DistortedCamera();
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector2d pixel(u(rng) * camera.width, u(rng) * camera.height);
    const Eigen::Vector3d ray = camera.Ray(pixel);
    EXPECT_LT((camera.Project(ray) - pixel).norm(), 1e-9) << pixel.transpose();
  }
}

TEST(ReadCamera, OurYamlAndOpenCvCalibrationAgree) {
  const std::string dir = testing::TempDirForThisTest("render");
  testing::WriteText(dir + "/ours.yaml",
                     "camera: {width: 1280, height: 800, fx: 881.5, fy: 880.25, cx: 641.2, "
                     "cy: 398.7, distortion: [-0.21, 0.06, 0.0012, -0.0007, -0.01]}\n");
  // As OpenCV's calibration sample writes it (cv::FileStorage).
  testing::WriteText(dir + "/opencv.yml",
                     "%YAML:1.0\n---\nimage_width: 1280\nimage_height: 800\n"
                     "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                     "   data: [ 881.5, 0., 641.2, 0., 880.25, 398.7, 0., 0., 1. ]\n"
                     "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
                     "   data: [ -0.21, 0.06, 0.0012, -0.0007, -0.01 ]\n");
  const PinholeCamera a = ReadCamera(dir + "/ours.yaml"), b = ReadCamera(dir + "/opencv.yml");
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_DOUBLE_EQ(a.fx, b.fx);
  EXPECT_DOUBLE_EQ(a.cy, b.cy);
  EXPECT_EQ(a.distortion, b.distortion);
}

TEST(ReadCamera, MissingFieldIsNamed) {
  const std::string dir = testing::TempDirForThisTest("render");
  testing::WriteText(dir + "/opencv.yml",
                     "%YAML:1.0\n---\nimage_width: 1280\nimage_height: 800\n"
                     "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                     "   data: [ 881.5, 0., 641.2, 0., 880.25, 398.7, 0., 0., 1. ]\n");
  const InputError e = testing::CatchInputError([&] { ReadCamera(dir + "/opencv.yml"); });
  EXPECT_THAT(e.what(), HasSubstr("missing field 'distortion_coefficients'"));
  const InputError ours = testing::CatchInputError([&] {
    testing::WriteText(dir + "/ours.yaml",
                       "camera: {width: 1280, height: 800, fx: 880, cx: 640, cy: 400}\n");
    ReadCamera(dir + "/ours.yaml");
  });
  EXPECT_THAT(ours.what(), HasSubstr("missing key 'fy'"));
}

// Random bytes and mangled files: every one is an InputError or a valid result, never a crash.
TEST(Readers, SurviveFuzzedInput) {
  const std::string dir = testing::TempDirForThisTest("render");
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> byte(0, 255);
  GrayImage small(16, 12, 100);
  WriteGrayImage(small, dir + "/valid.png");
  const std::string png = testing::ReadText(dir + "/valid.png");
  const std::string yaml =
      "camera: {width: 1280, height: 800, fx: 880, fy: 880, cx: 640, cy: 400}\n";
  for (int i = 0; i < 300; ++i) {
    std::string image = png, camera = yaml;
    const int flips = 1 + i % 8;
    for (int k = 0; k < flips; ++k) {
      image[std::uniform_int_distribution<size_t>(0, image.size() - 1)(rng)] =
          static_cast<char>(byte(rng));
      camera[std::uniform_int_distribution<size_t>(0, camera.size() - 1)(rng)] =
          static_cast<char>(byte(rng));
    }
    if (i % 10 == 0) image.resize(image.size() / 2);  // truncated
    testing::WriteText(dir + "/fuzz.png", image);
    testing::WriteText(dir + "/fuzz.yaml", camera);
    try {
      const GrayImage read = ReadGrayImage(dir + "/fuzz.png");
      EXPECT_GT(read.width(), 0);
    } catch (const InputError&) {
    }
    try {
      const PinholeCamera read = ReadCamera(dir + "/fuzz.yaml");
      EXPECT_GT(read.fx, 0);
    } catch (const InputError&) {
    }
  }
  testing::WriteText(dir + "/empty.png", "");
  EXPECT_THAT(testing::CatchInputError([&] { ReadGrayImage(dir + "/empty.png"); }).what(),
              HasSubstr("empty"));
  testing::WriteText(dir + "/text.png", "not an image at all");
  EXPECT_THAT(testing::CatchInputError([&] { ReadGrayImage(dir + "/text.png"); }).what(),
              HasSubstr("cannot be decoded"));
}

// A file that begins like a PGM and carries DICOM's mark at byte 128 (found by fuzz_image): OpenCV
// offered it to GDCM, whose reader aborts the process. It must be an InputError instead.
TEST(Readers, RefuseADicomMarkedFileWithoutDecodingIt) {
  const std::string dir = testing::TempDirForThisTest("render_dicom");
  std::string bytes = "P5\x08";  // "P5" without the whitespace a netpbm header needs
  bytes.resize(128, '\0');
  bytes += "DICM";
  bytes += std::string(64, 'Z');
  testing::WriteText(dir + "/frame.pgm", bytes);
  EXPECT_THAT(testing::CatchInputError([&] { ReadGrayImage(dir + "/frame.pgm"); }).what(),
              HasSubstr("cannot be decoded"));
  bytes[2] = ' ';  // a netpbm header now, but the DICOM mark still refuses it
  testing::WriteText(dir + "/frame.pgm", bytes);
  EXPECT_THAT(testing::CatchInputError([&] { ReadGrayImage(dir + "/frame.pgm"); }).what(),
              HasSubstr("cannot be decoded"));
}

// A marker frame facing the camera (its z axis out of the paper, toward the camera: OpenCV's
// marker convention), at `t` in the camera frame.
Pose Facing(const Eigen::Vector3d& t) {
  return Pose{Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix(), t};
}

// A black disk on white paper, 20 mm across.
std::vector<MarkerFace> DiskFace() {
  MarkerFace face;
  face.mm_per_texel = 0.05;
  face.texture = GrayImage(800, 800, 255);  // 40 x 40 mm
  for (int y = 0; y < 800; ++y) {
    for (int x = 0; x < 800; ++x) {
      const double dx = (x + 0.5) * 0.05 - 20, dy = (y + 0.5) * 0.05 - 20;
      if (dx * dx + dy * dy < 100.0) face.texture.at(x, y) = 0;
    }
  }
  face.T_target_face.t = Eigen::Vector3d(-20, -20, 0);  // disk centre at the target origin
  return {face};
}

TEST(Render, FrontoParallelDiskIsCentredOnItsProjection) {
  const PinholeCamera camera = OakDLikeCamera();
  const auto faces = DiskFace();
  const Pose T_cam_target = Facing(Eigen::Vector3d(13.7, -8.2, 400.0));
  RenderOptions options;
  options.illumination_gradient.setZero();
  const std::vector<float> ideal = RenderIdeal(camera, {{T_cam_target, &faces}}, options);
  const Eigen::Vector2d truth = camera.Project(T_cam_target.t);
  // Darkness-weighted centroid over the neighbourhood of the disk.
  double sw = 0, sx = 0, sy = 0;
  for (int y = static_cast<int>(truth.y()) - 40; y <= truth.y() + 40; ++y) {
    for (int x = static_cast<int>(truth.x()) - 40; x <= truth.x() + 40; ++x) {
      const double w = options.white - ideal[static_cast<size_t>(y) * camera.width + x];
      sw += w, sx += w * x, sy += w * y;
    }
  }
  EXPECT_LT((Eigen::Vector2d(sx / sw, sy / sw) - truth).norm(), 0.01);
  // Far from the face: background. Seen from behind, the paper is not seen at all.
  const Pose behind{Eigen::Matrix3d::Identity(), T_cam_target.t};
  const std::vector<float> back = RenderIdeal(camera, {{behind, &faces}}, options);
  EXPECT_FLOAT_EQ(
      back[static_cast<size_t>(std::lround(truth.y())) * camera.width + std::lround(truth.x())],
      static_cast<float>(options.background));
  EXPECT_FLOAT_EQ(ideal[5], static_cast<float>(options.background));
}

// The bound follows the information in the picture: the same disk twice as far away has half the
// edge length in pixels, so its image position is less certain. (Detectors are checked against
// it in their own tests: the dot's spread is 0.99x this bound.)
TEST(Render, CramerRaoGrowsWhenTheTargetShrinks) {
  const PinholeCamera camera = OakDLikeCamera();
  const auto faces = DiskFace();
  auto bound = [&](double z) {
    const std::vector<float> ideal =
        RenderIdeal(camera, {{Facing(Eigen::Vector3d(0, 0, z)), &faces}}, RenderOptions());
    return ImageShiftCramerRao(ideal, camera.width, camera.height, 2.0);
  };
  const Eigen::Vector2d near = bound(400.0), far = bound(800.0);
  EXPECT_GT(near.x(), 0.0);
  EXPECT_LT(near.x(), 0.05);  // a 44 px disk with sharp edges: a few hundredths of a pixel
  EXPECT_GT(far.x(), 1.2 * near.x());
  EXPECT_GT(far.y(), 1.2 * near.y());
}

// Many noisy views of one scene are one RenderIdeal and a SensorImage each (the detectors'
// bias tests draw 200): the same images RenderView makes from the same generator, noise that is
// fresh at every draw, and a clear error for an ideal image of the wrong size.
TEST(Render, SensorImageOfTheIdealIsRenderView) {
  const PinholeCamera camera = OakDLikeCamera();
  const auto faces = DiskFace();
  const std::vector<PlacedTarget> scene{{Facing(Eigen::Vector3d(5.0, 3.0, 420.0)), &faces}};
  const RenderOptions options;
  std::mt19937 a(11), b(11);
  const std::vector<float> ideal = RenderIdeal(camera, scene, options);
  const GrayImage first = SensorImage(ideal, camera.width, camera.height, options, a);
  const GrayImage second = SensorImage(ideal, camera.width, camera.height, options, a);
  const GrayImage rendered_first = RenderView(camera, scene, options, b);
  const GrayImage rendered_second = RenderView(camera, scene, options, b);
  const size_t n = static_cast<size_t>(camera.width) * camera.height;
  EXPECT_TRUE(std::equal(first.data(), first.data() + n, rendered_first.data()));
  EXPECT_TRUE(std::equal(second.data(), second.data() + n, rendered_second.data()));
  EXPECT_FALSE(std::equal(first.data(), first.data() + n, second.data()));
  EXPECT_THROW(SensorImage(ideal, camera.width, camera.height - 1, options, a),
               std::invalid_argument);
}

}  // namespace
}  // namespace cellmetry
