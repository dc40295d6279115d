// The board detector plugins, `checkerboard` (findChessboardCornersSB) and `charuco` (OpenCV 4.6
// contrib): their printed boards rendered at known poses with a known pinhole camera, detected,
// and the pose estimated from the keypoints (target_pose.h, solvePnP then Gauss-Newton) against
// the truth; the corner order whatever way the board is turned; a board cut by the image border;
// OpenCV's own photographs (opencv-doc: the calibration sample's left01..left14.jpg, the ChArUco
// tutorial's choriginal.jpg); and bad options.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/imaging/target_pose.h"
#include "cellmetry/model/camera.h"
#include "support/detector_views.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

const char kCheckerboard[] = "{type: checkerboard, corners_x: 9, corners_y: 6, square_mm: 20}";
const char kCharuco[] =
    "{type: charuco, dictionary: DICT_5X5_100, squares_x: 7, squares_y: 5, square_mm: 30, "
    "marker_mm: 22}";

using testing::Facing;
using testing::LayoutCentre;
using testing::MakeDetector;
using testing::RotationDeg;

// Poses 330..600 mm away, tilted up to 35 degrees and turned in the image plane by 0, 90, 180
// and -90 degrees: every order findChessboardCornersSB may list the corners in.
std::vector<Pose> TestPoses(const Detector& d, const std::vector<MarkerFace>& faces) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  return {Facing(d, faces, {0, 0, 330}, Eigen::Matrix3d::Identity()),
          Facing(d, faces, {20, -15, 380}, RotationDeg(x, 25)),
          Facing(d, faces, {-25, 10, 420}, RotationDeg(y, -30) * RotationDeg(z, 90)),
          Facing(d, faces, {15, 20, 480}, RotationDeg(x + y, 35) * RotationDeg(z, 180)),
          Facing(d, faces, {-20, -25, 540}, RotationDeg(x - 0.5 * y, 20) * RotationDeg(z, -90)),
          Facing(d, faces, {10, 5, 600}, RotationDeg(y, 15) * RotationDeg(z, 160))};
}

struct Scores {
  double worst_corner_px = 0.0;
  double worst_rotation_deg = 0.0;
  double worst_translation_mm = 0.0;
  size_t fewest_corners = 1 << 30;
};

// Renders the detector's board at each pose (blur 0.6 px, noise 2 gray levels), detects it and
// estimates its pose from the keypoints; every keypoint's id must be in the layout.
Scores Measure(Detector& d, const std::vector<Pose>& poses, unsigned seed) {
  const PinholeCamera camera = OakDLikeCamera();
  const std::vector<MarkerFace> faces = d.Faces(10.0);
  std::mt19937 rng(seed);
  Scores scores;
  for (const Pose& T_cam_target : poses) {
    SCOPED_TRACE("pose t = " + std::to_string(T_cam_target.t.z()) + " mm");
    std::map<int, Eigen::Vector2d> truth;
    for (const Keypoint& k : ProjectLayout(camera, T_cam_target, d.layout())) truth[k.id] = k.pixel;
    const Detection detection =
        d.Detect(RenderView(camera, {{T_cam_target, &faces}}, RenderOptions(), rng).view());
    EXPECT_TRUE(detection.found()) << detection.failure;
    scores.fewest_corners = std::min(scores.fewest_corners, detection.keypoints.size());
    double worst_here = 0.0;
    Eigen::Vector2d mean_here = Eigen::Vector2d::Zero();
    for (const Keypoint& k : detection.keypoints) {
      const auto it = truth.find(k.id);
      if (it == truth.end()) {
        ADD_FAILURE() << "keypoint id " << k.id << " is not in the layout";
        continue;
      }
      worst_here = std::max(worst_here, (k.pixel - it->second).norm());
      mean_here += (k.pixel - it->second) / detection.keypoints.size();
    }
    std::printf("  pose at %.0f mm: worst corner %.3f px, mean (%+.3f, %+.3f) px\n",
                T_cam_target.t.z(), worst_here, mean_here.x(), mean_here.y());
    scores.worst_corner_px = std::max(scores.worst_corner_px, worst_here);
    const std::optional<TargetPose> pose =
        EstimateTargetPose(camera, detection.keypoints, d.layout());
    if (!pose) {
      ADD_FAILURE() << "no pose";
      continue;
    }
    const Eigen::AngleAxisd rotation_error(pose->T_cam_target.R * T_cam_target.R.transpose());
    scores.worst_rotation_deg =
        std::max(scores.worst_rotation_deg, rotation_error.angle() * 180.0 / M_PI);
    scores.worst_translation_mm =
        std::max(scores.worst_translation_mm, (pose->T_cam_target.t - T_cam_target.t).norm());
  }
  return scores;
}

void Print(const std::string& name, const Scores& s) {
  std::printf(
      "[ board ] %-28s worst corner %.3f px, worst pose error %.4f deg / %.3f mm, fewest "
      "corners %zu\n",
      name.c_str(), s.worst_corner_px, s.worst_rotation_deg, s.worst_translation_mm,
      s.fewest_corners);
}

// --- Rendered views: poses from the keypoints against the truth.

TEST(CheckerboardDetector, PoseOnRenderedViewsMatchesTruth) {
  const auto d = MakeDetector(kCheckerboard);
  ASSERT_EQ(d->layout().size(), 54u);
  const Scores s = Measure(*d, TestPoses(*d, d->Faces(10.0)), 1);
  Print("checkerboard 9x6", s);
  EXPECT_EQ(s.fewest_corners, 54u);  // the whole board, every time
  EXPECT_LT(s.worst_corner_px, 0.1);
  EXPECT_LT(s.worst_rotation_deg, 0.05);
  EXPECT_LT(s.worst_translation_mm, 0.1);
}

// The detection options against the defaults (printed, not checked; docs/markers.md quotes them).
TEST(CheckerboardDetector, OptionVariantsOnRenderedViews) {
  const auto d = MakeDetector(kCheckerboard);
  const auto poses = TestPoses(*d, d->Faces(10.0));
  for (const char* variant : {"accuracy: false", "normalize_image: true", "exhaustive: true"}) {
    const auto v = MakeDetector(std::string(kCheckerboard).substr(0, sizeof(kCheckerboard) - 2) +
                                ", " + variant + "}");
    Print(std::string("checkerboard 9x6 (") + variant + ")", Measure(*v, poses, 1));
  }
}

TEST(CharucoDetector, PoseOnRenderedViewsMatchesTruth) {
  const auto d = MakeDetector(kCharuco);
  ASSERT_EQ(d->layout().size(), 24u);  // (7 - 1) x (5 - 1) inner corners
  const Scores s = Measure(*d, TestPoses(*d, d->Faces(10.0)), 2);
  Print("charuco 7x5 DICT_5X5_100", s);
  EXPECT_EQ(s.fewest_corners, 24u);
  // One noisy render per pose, windows of 5 px half-width (the markers' sides are 6-12 px away).
  EXPECT_LT(s.worst_corner_px, 0.15);
  EXPECT_LT(s.worst_rotation_deg, 0.05);
  EXPECT_LT(s.worst_translation_mm, 0.1);
}

// Without the plugin's last cornerSubPix: OpenCV's corners, its 0.5 px shift taken off (printed).
TEST(CharucoDetector, OpenCvCornersOnRenderedViews) {
  const auto d = MakeDetector(kCharuco);
  const auto v =
      MakeDetector(std::string(kCharuco).substr(0, sizeof(kCharuco) - 2) + ", subpix: false}");
  Print("charuco 7x5 (subpix: false)", Measure(*v, TestPoses(*d, d->Faces(10.0)), 2));
}

// Half the ChArUco board out of the frame: the corners in view are found, the pose holds.
TEST(CharucoDetector, BoardCutByTheImageBorder) {
  const auto d = MakeDetector(kCharuco);
  const auto faces = d->Faces(10.0);
  const PinholeCamera camera = OakDLikeCamera();
  // The board's centre 20 mm left of the frame's right edge at 400 mm.
  const Pose pose = Facing(*d, faces, {0.5 * camera.width * 400 / camera.fx - 20, 0, 400},
                           RotationDeg(Eigen::Vector3d::UnitY(), 10));
  const Scores s = Measure(*d, {pose}, 3);
  Print("charuco 7x5, cut by the border", s);
  EXPECT_LT(s.fewest_corners, 24u);
  EXPECT_GE(s.fewest_corners, 8u);
  EXPECT_LT(s.worst_corner_px, 0.15);
  EXPECT_LT(s.worst_rotation_deg, 0.1);
  EXPECT_LT(s.worst_translation_mm, 0.2);
}

// The checkerboard needs the whole board: cut by the border, it is not found, and says why.
TEST(CheckerboardDetector, BoardCutByTheImageBorderIsNotFound) {
  const auto d = MakeDetector(kCheckerboard);
  const auto faces = d->Faces(10.0);
  const PinholeCamera camera = OakDLikeCamera();
  const Pose pose = Facing(*d, faces, {0.5 * camera.width * 400 / camera.fx - 20, 0, 400},
                           Eigen::Matrix3d::Identity());
  std::mt19937 rng(4);
  const Detection detection =
      d->Detect(RenderView(camera, {{pose, &faces}}, RenderOptions(), rng).view());
  EXPECT_FALSE(detection.found());
  EXPECT_THAT(detection.failure, HasSubstr("whole board must be in view"));
}

// layout() is where OpenCV 4.6's CharucoBoard puts the chessboard corners, and the printed face
// is what CharucoBoard::draw prints (at a texel size where both are exact).
TEST(CharucoDetector, BoardAgreesWithOpenCvCharucoBoard) {
  const auto d = MakeDetector(
      "{type: charuco, dictionary: DICT_6X6_250, squares_x: 5, squares_y: 7, square_mm: 24, "
      "marker_mm: 16}");
  const auto board = cv::aruco::CharucoBoard::create(
      5, 7, 24.f, 16.f, cv::aruco::getPredefinedDictionary(cv::aruco::DICT_6X6_250));
  ASSERT_EQ(d->layout().size(), board->chessboardCorners.size());
  for (const MarkerPoint& p : d->layout()) {
    const cv::Point3f& q = board->chessboardCorners[p.id];
    EXPECT_LT((p.p_target_mm - Eigen::Vector3d(q.x, q.y, q.z)).norm(), 1e-4) << p.id;
  }
  // 1 texel per mm: a bit cell (16/8 mm) is 2 texels, a square 24, the margin (a square) 24.
  const auto faces = d->Faces(1.0);
  ASSERT_EQ(faces.size(), 1u);
  const GrayImage& texture = faces[0].texture;
  EXPECT_NEAR(faces[0].mm_per_texel, 1.0, 1e-12);
  cv::Mat printed;
  board->draw(cv::Size(texture.width(), texture.height()), printed, 24, 1);
  int differ = 0;
  for (int y = 0; y < texture.height(); ++y) {
    for (int x = 0; x < texture.width(); ++x) {
      // Texture rows run up the face's y axis; the printed image's rows run down.
      differ += texture.at(x, texture.height() - 1 - y) != printed.at<std::uint8_t>(y, x);
    }
  }
  EXPECT_EQ(differ, 0);
}

TEST(Boards, KeypointCovarianceIsSigmaSquared) {
  for (const std::string yaml :
       {"{type: checkerboard, corners_x: 9, corners_y: 6, square_mm: 20, sigma_px: 0.2}",
        "{type: charuco, dictionary: DICT_5X5_100, squares_x: 7, squares_y: 5, square_mm: 30, "
        "marker_mm: 22, sigma_px: 0.2}"}) {
    const auto d = MakeDetector(yaml);
    const auto faces = d->Faces(10.0);
    std::mt19937 rng(1);
    const Detection detection = d->Detect(
        RenderView(OakDLikeCamera(),
                   {{Facing(*d, faces, {0, 0, 400}, Eigen::Matrix3d::Identity()), &faces}},
                   RenderOptions(), rng)
            .view());
    ASSERT_EQ(detection.keypoints.size(), d->layout().size()) << yaml << detection.failure;
    for (const Keypoint& k : detection.keypoints) {
      EXPECT_LT((k.covariance_px2 - 0.04 * Eigen::Matrix2d::Identity()).norm(), 1e-12);
    }
  }
}

// --- OpenCV's photographs (opencv-doc).

const char kDocData[] = "/usr/share/doc/opencv-doc/examples/data/";
const char kDocImages[] = "/usr/share/doc/opencv-doc/opencv4/html/";

// OpenCV's calibration sample's left camera: 13 views of a 9 x 6 inner-corner board of 25 mm
// squares (left10.jpg is not shipped), and the calibration OpenCV's sample made from them
// (left_intrinsics.yml: fx = fy = 535.9 px, cx 342.3, cy 235.6, 0.39 px RMS). Every corner of
// every view is found; the top-left square, which the corner order rests on, is black in every
// view (checked on the outer squares, which the order does not look at); and calibrateCamera on
// the keypoints reproduces OpenCV's calibration.
TEST(CheckerboardPhotos, OpenCvCalibrationSample) {
  const std::string intrinsics = std::string(kDocData) + "left_intrinsics.yml";
  if (!std::filesystem::exists(intrinsics)) GTEST_SKIP() << intrinsics << " is not installed";
  const auto d = MakeDetector("{type: checkerboard, corners_x: 9, corners_y: 6, square_mm: 25}");
  std::vector<cv::Point3f> object;
  for (const MarkerPoint& p : d->layout()) {
    object.emplace_back(static_cast<float>(p.p_target_mm.x()),
                        static_cast<float>(p.p_target_mm.y()), 0.f);
  }
  std::vector<std::vector<cv::Point3f>> objects;
  std::vector<std::vector<cv::Point2f>> images;
  int views = 0;
  for (int i = 1; i <= 14; ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "left%02d.jpg", i);
    const std::string path = std::string(kDocData) + name;
    if (!std::filesystem::exists(path)) continue;
    ++views;
    const GrayImage image = ReadGrayImage(path);
    const Detection detection = d->Detect(image.view());
    ASSERT_TRUE(detection.found()) << name << ": " << detection.failure;
    ASSERT_EQ(detection.keypoints.size(), 54u) << name;
    std::vector<cv::Point2f> pixels;
    for (const Keypoint& k : detection.keypoints) {
      pixels.emplace_back(static_cast<float>(k.pixel.x()), static_cast<float>(k.pixel.y()));
    }
    // The outer squares, a quarter square outside the corner grid (this board's outer squares
    // are cut short), by the homography of the corners: top-left black, bottom-right white.
    std::vector<cv::Point2f> plane;
    for (const cv::Point3f& p : object) plane.emplace_back(p.x, p.y);
    const cv::Mat H = cv::findHomography(plane, pixels);
    std::vector<cv::Point2f> outer = {{-6.25f, -6.25f}, {206.25f, 131.25f}}, outer_px;
    cv::perspectiveTransform(outer, outer_px, H);
    const cv::Mat gray(image.height(), image.width(), CV_8UC1,
                       const_cast<std::uint8_t*>(image.data()));
    const int top_left = gray.at<std::uint8_t>(cv::Point(outer_px[0]));
    const int bottom_right = gray.at<std::uint8_t>(cv::Point(outer_px[1]));
    EXPECT_LT(top_left + 60, bottom_right) << name << ": the top-left square is not the black one";
    objects.push_back(object);
    images.push_back(pixels);
  }
  ASSERT_EQ(views, 13);
  cv::Mat K = cv::Mat::eye(3, 3, CV_64F), dist, rvecs, tvecs;
  const double rms = cv::calibrateCamera(objects, images, cv::Size(640, 480), K, dist, rvecs, tvecs,
                                         cv::CALIB_FIX_ASPECT_RATIO);
  cv::FileStorage opencv(intrinsics, cv::FileStorage::READ);
  cv::Mat K_opencv;
  opencv["camera_matrix"] >> K_opencv;
  std::printf(
      "[ photo ] left01..14.jpg: 13 of 13 views, 54 of 54 corners each; calibrateCamera %.3f px "
      "RMS, fx %.1f cx %.1f cy %.1f (OpenCV's sample: 0.393 px, %.1f %.1f %.1f)\n",
      rms, K.at<double>(0, 0), K.at<double>(0, 2), K.at<double>(1, 2), K_opencv.at<double>(0, 0),
      K_opencv.at<double>(0, 2), K_opencv.at<double>(1, 2));
  EXPECT_LT(rms, 0.393);
  EXPECT_NEAR(K.at<double>(0, 0), K_opencv.at<double>(0, 0), 0.01 * K_opencv.at<double>(0, 0));
  EXPECT_NEAR(K.at<double>(0, 2), K_opencv.at<double>(0, 2), 5.0);
  EXPECT_NEAR(K.at<double>(1, 2), K_opencv.at<double>(1, 2), 5.0);
}

// The ChArUco tutorial's photograph (its other ChArUco images have detections drawn over them):
// OpenCV's board of 5 x 7 squares, DICT_6X6_250, markers half the square. Every keypoint's id is
// checked by the homography of all the others (a corner given the wrong id lands a square or
// more away from where they put it).
void ExpectCharucoPhoto(const std::string& image_name, size_t min_corners) {
  const std::string path = std::string(kDocImages) + image_name;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not installed (opencv-doc)";
  // The board as configs/boards/ gives it.
  const ConfigNode config =
      ConfigNode::LoadFile(testing::Source("configs/boards/charuco_5x7_40mm.yaml"))["detector"];
  const auto d = testing::Plugins().CreateDetector(config["type"].AsString(), config);
  const Detection detection = d->Detect(ReadGrayImage(path).view());
  ASSERT_TRUE(detection.found()) << detection.failure;
  EXPECT_GE(detection.keypoints.size(), min_corners) << image_name;
  std::map<int, Eigen::Vector3d> layout;
  for (const MarkerPoint& p : d->layout()) layout[p.id] = p.p_target_mm;
  double worst = 0.0;
  for (size_t left_out = 0; left_out < detection.keypoints.size(); ++left_out) {
    std::vector<cv::Point2f> plane, pixels;
    for (size_t i = 0; i < detection.keypoints.size(); ++i) {
      if (i == left_out) continue;
      const Keypoint& k = detection.keypoints[i];
      plane.emplace_back(static_cast<float>(layout.at(k.id).x()),
                         static_cast<float>(layout.at(k.id).y()));
      pixels.emplace_back(static_cast<float>(k.pixel.x()), static_cast<float>(k.pixel.y()));
    }
    const cv::Mat H = cv::findHomography(plane, pixels);
    const Keypoint& k = detection.keypoints[left_out];
    std::vector<cv::Point2f> predicted;
    cv::perspectiveTransform(std::vector<cv::Point2f>{{static_cast<float>(layout.at(k.id).x()),
                                                       static_cast<float>(layout.at(k.id).y())}},
                             predicted, H);
    const double error = std::hypot(predicted[0].x - k.pixel.x(), predicted[0].y - k.pixel.y());
    worst = std::max(worst, error);
    EXPECT_LT(error, 2.0) << image_name << " corner " << k.id;
  }
  std::printf(
      "[ photo ] %-18s %zu of %zu chessboard corners, worst left-out homography error %.2f px\n",
      image_name.c_str(), detection.keypoints.size(), d->layout().size(), worst);
}

TEST(CharucoPhotos, TutorialBoard) { ExpectCharucoPhoto("choriginal.jpg", 24); }

// --- Bad input: InputError naming the file and line, and what to do; failures in words.

TEST(BoardBadInput, WrongOptionsAreRefusedWithAMessage) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{type: checkerboard, corners_x: 9, corners_y: 7, square_mm: 20}",
       "looks the same turned by 180 degrees"},
      {"{type: checkerboard, corners_x: 2, corners_y: 5, square_mm: 20}", "must be at least 3"},
      {"{type: checkerboard, corners_x: 9, square_mm: 20}", "missing key 'corners_y'"},
      {"{type: checkerboard, corners_x: 9, corners_y: 6, square_mm: -20}", "must be positive"},
      {"{type: checkerboard, corners_x: 9, corners_y: 6}", "missing key 'square_mm'"},
      {"{type: checkerboard, corners_x: 9, corners_y: 6, square_mm: 20, accuracy: maybe}",
       "accuracy"},
      {"{type: checkerboard, corners_x: 9, corners_y: 6, square_size: 20}",
       "square_size: unknown key. Known keys: type, corners_x, corners_y, square_mm"},
      {"{type: charuco, squares_x: 5, squares_y: 7, square_mm: 40, marker_mm: 20}",
       "exactly one of dictionary and dictionary_file"},
      {"{type: charuco, dictionary: DICT_6X6_25O, squares_x: 5, squares_y: 7, square_mm: 40, "
       "marker_mm: 20}",
       "Did you mean 'DICT_6X6_250'"},
      {"{type: charuco, dictionary: DICT_6X6_250, squares_x: 5, squares_y: 7, square_mm: 40, "
       "marker_mm: 40}",
       "a marker must be smaller than its square"},
      {"{type: charuco, dictionary: DICT_4X4_50, squares_x: 11, squares_y: 11, square_mm: 40, "
       "marker_mm: 20}",
       "dictionary has ids 0..49"},
      {"{type: charuco, dictionary: DICT_6X6_250, squares_x: 1, squares_y: 7, square_mm: 40, "
       "marker_mm: 20}",
       "must be at least 2"},
      {"{type: charuco, dictionary: DICT_6X6_250, squares_x: 5, squares_y: 7, square_mm: 40, "
       "marker_mm: 20, min_markers: 3}",
       "must be 1 or 2"},
  };
  for (const auto& [yaml_text, text] : cases) {
    const auto& yaml = yaml_text;  // C++17: a lambda cannot capture a structured binding (clang)
    const InputError e = testing::CatchInputError([&] { MakeDetector(yaml); });
    EXPECT_THAT(e.what(), HasSubstr(text)) << yaml;
    EXPECT_THAT(e.what(), HasSubstr("test.yaml:1:")) << yaml;
  }
}

// The error names the option's line in a job file and says what to use instead.
TEST(BoardBadInput, ErrorNamesTheLineAndTheFix) {
  const ConfigNode config = ConfigNode::LoadString(
      "type: checkerboard\ncorners_x: 8\ncorners_y: 6\nsquare_mm: 25\n", "job.yaml");
  const InputError e =
      testing::CatchInputError([&] { testing::Plugins().CreateDetector("checkerboard", config); });
  EXPECT_THAT(e.what(), HasSubstr("job.yaml:"));
  EXPECT_THAT(e.what(), HasSubstr("one even and one odd count of inner corners"));
}

TEST(BoardBadInput, BlankImageFailsInWords) {
  const GrayImage blank(1280, 800, 128);
  const auto checkerboard = MakeDetector(kCheckerboard);
  EXPECT_THAT(checkerboard->Detect(blank.view()).failure,
              HasSubstr("no 9 x 6 inner-corner checkerboard found"));
  const auto charuco = MakeDetector(kCharuco);
  EXPECT_THAT(charuco->Detect(blank.view()).failure,
              HasSubstr("no chessboard corner of this DICT_5X5_100 ChArUco board found"));
  EXPECT_THAT(checkerboard->Detect(ImageView{}).failure, HasSubstr("empty"));
  EXPECT_THAT(charuco->Detect(ImageView{}).failure, HasSubstr("empty"));
}

// Markers of another board in view are not this board's corners, and the failure says so.
TEST(BoardBadInput, OtherMarkersAreNamed) {
  const auto printed = MakeDetector(
      "{type: aruco, dictionary: DICT_5X5_100, marker_length_mm: 40, marker_ids: [60]}");
  const auto faces = printed->Faces(10.0);
  std::mt19937 rng(4);
  const GrayImage image =
      RenderView(OakDLikeCamera(),
                 {{Facing(*printed, faces, {0, 0, 400}, Eigen::Matrix3d::Identity()), &faces}},
                 RenderOptions(), rng);
  const Detection d = MakeDetector(kCharuco)->Detect(image.view());
  EXPECT_FALSE(d.found());
  EXPECT_THAT(d.failure, HasSubstr("other marker ids (60)"));
}

TEST(Boards, RegisteredWithDocumentedOptions) {
  std::map<std::string, PluginInfo> infos;
  for (const PluginInfo& info : testing::Plugins().List()) infos[info.name] = info;
  for (const char* name : {"checkerboard", "charuco"}) {
    ASSERT_TRUE(infos.count(name)) << name;
    EXPECT_EQ(infos[name].kind, PluginKind::kDetector);
    EXPECT_FALSE(infos[name].description.empty());
    EXPECT_GE(infos[name].options.size(), 6u);
    for (const OptionDoc& option : infos[name].options) {
      EXPECT_FALSE(option.description.empty()) << option.name;
    }
  }
}

}  // namespace
}  // namespace cellmetry
