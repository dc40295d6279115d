// `cellmetry detect`'s pipeline: rendered stereo images of the delta arm's marker, a detector,
// resumable per-image log, failures recorded with reasons, triangulated observations vs truth.
// A small centroid detector defined here keeps the pipeline's test independent of the detector
// plugins (they have their own tests).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/imaging/detection.h"
#include "cellmetry/imaging/image_simulation.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

// A black disk, 12 mm across, on a white 30 mm square; keypoint 0 = the disk's centre.
class CentroidDetector : public Detector {
 public:
  Detection Detect(const ImageView& image) override {
    double sw = 0, sx = 0, sy = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        // Darker than the background (60) and the white paper: only the disk (25) counts.
        const double w = std::max(0.0, 45.0 - image.at(x, y));
        sw += w, sx += w * x, sy += w * y;
      }
    }
    Detection d;
    if (sw < 100) {
      d.failure = "no dark blob";
      return d;
    }
    Keypoint k;
    k.pixel = Eigen::Vector2d(sx / sw, sy / sw);
    k.covariance_px2 = Eigen::Matrix2d::Identity() * 0.05 * 0.05;
    d.keypoints.push_back(k);
    return d;
  }
  const std::vector<MarkerPoint>& layout() const override { return layout_; }
  std::vector<MarkerFace> Faces(double texels_per_mm) const override {
    MarkerFace face;
    face.mm_per_texel = 0.05;
    face.texture = GrayImage(600, 600, 255);
    for (int y = 0; y < 600; ++y) {
      for (int x = 0; x < 600; ++x) {
        const double dx = (x + 0.5) * 0.05 - 15, dy = (y + 0.5) * 0.05 - 15;
        if (dx * dx + dy * dy < 36.0) face.texture.at(x, y) = 0;
      }
    }
    face.T_target_face.t = Eigen::Vector3d(-15, -15, 0);
    return {face};
  }

 private:
  std::vector<MarkerPoint> layout_ = {{0, Eigen::Vector3d::Zero()}};
};

void RegisterCentroidDetector() {
  static const bool once = [] {
    PluginInfo info;
    info.name = "test_centroid";
    info.description = "dark-blob centroid (tests only)";
    testing::Plugins().AddDetector(
        info, [](const ConfigNode&) { return std::make_unique<CentroidDetector>(); });
    return true;
  }();
  (void)once;
}

class Detection : public ::testing::Test {
 protected:
  void SetUp() override {
    RegisterCentroidDetector();
    dir_ = testing::TempDirForThisTest("detection");
    WorkcellSimulationSpec spec = LoadWorkcellSimulation(
        testing::Source("configs/simulations/delta_uniform_125.yaml"), testing::Plugins());
    spec.robots.front().pose_set = PoseSetSpec{PoseSet::kCameraView, 12, ""};
    std::mt19937 rng(3);
    const SimulatedDraw draw = DrawAndSimulate(spec, rng);
    Recording recording = draw.recording;
    recording.observations.clear();
    views_ = WorkcellViews(draw.truth, recording);
    ImageRenderSpec images;
    images.markers = {ReadTargetMarker(
        kTarget, ConfigNode::LoadString("type: test_centroid", "test"), testing::Plugins())};
    images.cameras[kCamera].rig = OakDLikeRig();
    images.render.noise_sigma = 1.0;
    images.render.supersampling = 3;
    const auto write = PlanImages(images, views_, 5, testing::Plugins(), &recording);
    WriteRecording(recording, dir_ + "/rec", "", write);
    job_.recording = dir_ + "/rec";
    job_.targets = images.markers;
    job_.cameras = images.cameras;
  }

  int LogLines() {
    std::ifstream in(dir_ + "/rec/detections.jsonl");
    int n = 0;
    for (std::string line; std::getline(in, line);) ++n;
    return n;
  }

  std::string dir_;
  const std::string kTarget = "marker", kCamera = "stereo";
  std::vector<SampleView> views_;
  DetectJob job_;
};

TEST_F(Detection, InterruptedRunContinuesWithoutLosingOrDuplicatingImages) {
  const DetectSummary first = RunDetection(job_, testing::Plugins(), /*limit=*/7);
  EXPECT_EQ(first.processed, 7);
  EXPECT_EQ(LogLines(), 7);
  // A run killed in the middle of writing a line leaves a torn line behind.
  std::ofstream(dir_ + "/rec/detections.jsonl", std::ios::app) << "{\"sample\": 5, \"cam";
  const DetectSummary second = RunDetection(job_, testing::Plugins());
  EXPECT_EQ(second.already_done, 7);
  EXPECT_EQ(second.processed, 24 - 7);
  EXPECT_EQ(LogLines(), 24);  // 12 samples x 2 views, each once
  EXPECT_EQ(second.found, 24);
  EXPECT_EQ(second.observations, 12);
  const DetectSummary third = RunDetection(job_, testing::Plugins());
  EXPECT_EQ(third.processed, 0);
  EXPECT_EQ(LogLines(), 24);
}

TEST_F(Detection, TriangulatedObservationsAreWhereTheMarkerIs) {
  RunDetection(job_, testing::Plugins());
  const Recording detected = ReadRecording(dir_ + "/rec");
  ASSERT_EQ(detected.observations.size(), views_.size());
  for (const auto& o : detected.observations) {
    const auto view = std::find_if(views_.begin(), views_.end(),
                                   [&](const SampleView& v) { return v.sample == o.sample; });
    ASSERT_NE(view, views_.end());
    ASSERT_TRUE(o.covariance_mm2.has_value());
    // This test's centroid is biased by perspective (a few hundredths of a pixel, differently in
    // the two views), which depth magnifies: within 2 mm at 0.35-0.55 m. Detector accuracy is
    // the detector plugins' tests' business; this checks the pipeline puts points in place.
    EXPECT_LT((o.position_mm - view->T_cam_target.at(kTarget).t).norm(), 2.0)
        << "sample " << o.sample;
    EXPECT_GT((*o.covariance_mm2)(2, 2), (*o.covariance_mm2)(0, 0));  // depth is the weak axis
  }
}

TEST_F(Detection, BadImagesAreRecordedWithTheirReasonAndTheRunGoesOn) {
  testing::WriteText(dir_ + "/rec/images/0_" + kCamera + "_left.png", "this is not a png");
  testing::WriteText(dir_ + "/rec/images/1_" + kCamera + "_left.png", "");
  WriteGrayImage(GrayImage(640, 480, 128), dir_ + "/rec/images/2_" + kCamera + "_left.png");
  WriteGrayImage(GrayImage(1280, 800, 200),
                 dir_ + "/rec/images/3_" + kCamera + "_left.png");  // no marker
  fs::remove(dir_ + "/rec/images/4_" + kCamera + "_left.png");
  const DetectSummary s = RunDetection(job_, testing::Plugins());
  EXPECT_EQ(s.processed, 24);
  EXPECT_EQ(s.found, 19);
  std::string reasons;
  for (const auto& [reason, count] : s.failures) reasons += reason + "\n";
  EXPECT_THAT(reasons, HasSubstr("cannot be decoded"));
  EXPECT_THAT(reasons, HasSubstr("empty"));
  EXPECT_THAT(reasons, HasSubstr("image is 640x480, the calibration is for 1280x800"));
  EXPECT_THAT(reasons, HasSubstr("no dark blob"));
  EXPECT_THAT(reasons, HasSubstr("image not found"));
  EXPECT_EQ(s.observations, 7);
}

// `detect` replaces observations.csv whole: one it did not write is refused before any work,
// and left as it was; its own it replaces on the next run.
TEST_F(Detection, AnObservationsFileDetectDidNotWriteIsNeverReplaced) {
  const std::string mine = "sample,camera,target,x,y,z\n0,stereo,marker,1,2,3\n";
  testing::WriteText(dir_ + "/rec/observations.csv", mine);
  try {
    RunDetection(job_, testing::Plugins());
    ADD_FAILURE() << "a user's observations.csv was replaced";
  } catch (const InputError& e) {
    EXPECT_THAT(e.where().file, HasSubstr("rec/observations.csv"));
    EXPECT_THAT(e.message(), HasSubstr("was not written by cellmetry detect"));
    EXPECT_THAT(e.hint(), HasSubstr("Move the file out of the recording"));
  }
  EXPECT_EQ(testing::ReadText(dir_ + "/rec/observations.csv"), mine);
  EXPECT_FALSE(fs::exists(dir_ + "/rec/detections.jsonl")) << "work began before the refusal";
  fs::remove(dir_ + "/rec/observations.csv");
  RunDetection(job_, testing::Plugins(), /*limit=*/3);
  RunDetection(job_, testing::Plugins());  // its own file: replaced
  EXPECT_EQ(ReadRecording(dir_ + "/rec").observations.size(), 12u);
}

// The log is appended in place: a link would be written through to a file outside the
// recording.
TEST_F(Detection, ALinkedDetectionLogIsNotAppendedThrough) {
  testing::WriteText(dir_ + "/elsewhere.jsonl", "");
  fs::create_symlink(dir_ + "/elsewhere.jsonl", dir_ + "/rec/detections.jsonl");
  try {
    RunDetection(job_, testing::Plugins());
    ADD_FAILURE() << "the log was appended through a link";
  } catch (const InputError& e) {
    EXPECT_THAT(e.message(), HasSubstr("the detection log is a link"));
    EXPECT_THAT(e.hint(), HasSubstr("Replace the link by a copy of the file it names"));
  }
  EXPECT_EQ(testing::ReadText(dir_ + "/elsewhere.jsonl"), "");
}

// A key twice in a line of the log is a hand edit, refused at its line like any damage.
TEST_F(Detection, ALogLineWithAKeyTwiceIsRefusedAtItsLine) {
  RunDetection(job_, testing::Plugins(), /*limit=*/2);
  std::string log = testing::ReadText(dir_ + "/rec/detections.jsonl");
  log.insert(1, "\"sample\": 99, ");
  testing::WriteText(dir_ + "/rec/detections.jsonl", log);
  try {
    RunDetection(job_, testing::Plugins());
    ADD_FAILURE() << "a duplicate key was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 1);
    EXPECT_THAT(e.message(), HasSubstr("key 'sample' appears twice in one object"));
  }
}

}  // namespace
}  // namespace cellmetry
