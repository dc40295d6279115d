// End to end from pixels, through `cellmetry simulate` (images), `detect` and `run`:
//  - a rendered stereo recording of the delta arm (the white-dot plugin, kinematic calibration):
//    the arm's identifiable dimensions land within 3 sigma of the truth;
//  - a rendered UR3 cell seen by two mono cameras (an AprilTag grid board on the table, a tag
//    cube on the tool; workcell identification with the detector's systematic error carried as
//    a nuisance): base, tool and cameras within 3 sigma.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/formats/recording.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

TEST(EndToEndFromImages, DeltaArmThroughDetectAndRunLandsWithinThreeSigma) {
  const std::string dir = testing::TempDirForThisTest("end_to_end");
  const std::string rec = dir + "/images";
  auto run = [](const std::string& args) {
    const auto r = testing::RunCellmetry(args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.output;
    return r;
  };
  run("simulate " + testing::Source("configs/simulations/delta_images.yaml") + " -o " + rec);
  const std::string detect =
      testing::ReplaceOnce(testing::ReadText(testing::Source("configs/jobs/delta_detect.yaml")),
                           "recording: ../../results/delta_images", "recording: " + rec);
  testing::WriteText(dir + "/detect.yaml",
                     testing::ReplaceOnce(detect, "../cameras/oakd_like.yaml",
                                          testing::Source("configs/cameras/oakd_like.yaml")));
  run("detect " + dir + "/detect.yaml");
  std::string job =
      testing::ReadText(testing::Source("configs/jobs/delta_calibration_images.yaml"));
  job = testing::ReplaceOnce(job, "recording: ../../results/delta_images", "recording: " + rec);
  job = testing::ReplaceOnce(job, "model: ../robots/delta.yaml",
                             "model: " + testing::Source("configs/robots/delta.yaml"));
  testing::WriteText(dir + "/calibrate.yaml", job);
  run("run " + dir + "/calibrate.yaml -o " + dir + "/result");

  const nlohmann::json result =
      nlohmann::json::parse(testing::ReadText(dir + "/result/result.json"));
  const WorkcellTruth truth = ReadTruth(rec + "/truth.yaml");
  std::map<std::string, std::pair<double, double>> estimate;  // name -> value, sigma
  for (const auto& p : result["model_parameters"]) {
    estimate[p["name"].get<std::string>()] = {p["value"].get<double>(), p["sigma"].get<double>()};
  }
  ASSERT_EQ(estimate.size(), 12u);  // the job frees 4 of each arm's 5 entries
  const ConfigNode arms =
      ConfigNode::LoadFile(testing::Source("configs/robots/delta.yaml"))["arms"];
  for (int arm = 1; arm <= 3; ++arm) {
    const std::string a = "delta.model.arm" + std::to_string(arm) + ".";
    auto t = [&](const std::string& name) { return truth.model.at(a + name); };
    // R - r: r is held at nominal, so R carries the difference.
    const double r_nominal = arms.Elements()[arm - 1]["r"].AsDouble();
    const double diff_error = (estimate[a + "R"].first - r_nominal) - (t("R") - t("r"));
    EXPECT_LT(std::abs(diff_error), 3 * estimate[a + "R"].second) << a << "R-r";
    for (const std::string name : {"L", "l", "homing"}) {
      const auto [value, sigma] = estimate[a + name];
      EXPECT_LT(std::abs(value - t(name)), 3 * sigma) << a << name << " sigma " << sigma;
    }
  }
}

TEST(EndToEndFromImages, Ur3WithAprilTagCubeThroughDetectAndRunLandsWithinThreeSigma) {
  const std::string dir = testing::TempDirForThisTest("end_to_end_ur3");
  const std::string rec = dir + "/images";
  auto run = [](const std::string& args) {
    const auto r = testing::RunCellmetry(args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.output;
    return r;
  };
  const std::string camera = testing::Source("configs/cameras/ceiling_1280x720.yaml");
  std::string spec =
      testing::ReadText(testing::Source("configs/simulations/ur3_apriltag_images.yaml"));
  spec = testing::ReplaceOnce(spec, "../robots/ur3_vsb2020.yaml",
                              testing::Source("configs/robots/ur3_vsb2020.yaml"));
  spec = testing::ReplaceOnce(spec, "../../tests/data/vsb/sim_b",
                              testing::Source("tests/data/vsb/sim_b"));
  spec = testing::ReplaceOnce(spec, "every: 2", "every: 4");  // 63 poses: enough, and quick
  spec = testing::ReplaceOnce(spec, "../cameras/ceiling_1280x720.yaml", camera);
  testing::WriteText(dir + "/simulate.yaml", spec);
  run("simulate " + dir + "/simulate.yaml -o " + rec);

  std::string detect = testing::ReadText(testing::Source("configs/jobs/ur3_apriltag_detect.yaml"));
  detect = testing::ReplaceOnce(detect, "recording: ../../results/ur3_apriltag_images",
                                "recording: " + rec);
  detect = testing::ReplaceOnce(detect, "cam1: {mono: ../cameras/ceiling_1280x720.yaml}",
                                "cam1: {mono: " + camera + "}");
  detect = testing::ReplaceOnce(detect, "cam2: {mono: ../cameras/ceiling_1280x720.yaml}",
                                "cam2: {mono: " + camera + "}");
  testing::WriteText(dir + "/detect.yaml", detect);
  run("detect " + dir + "/detect.yaml");
  const Recording detected = ReadRecording(rec);
  // Both boards in both cameras in (nearly) every sample.
  EXPECT_GE(detected.observations.size(), 0.95 * 4 * detected.samples.size());

  std::string job = testing::ReadText(testing::Source("configs/jobs/ur3_apriltag_images.yaml"));
  job = testing::ReplaceOnce(job, "recording: ../../results/ur3_apriltag_images\n",
                             "recording: " + rec + "\n");
  job = testing::ReplaceOnce(job, "model: ../robots/ur3_vsb2020.yaml",
                             "model: " + testing::Source("configs/robots/ur3_vsb2020.yaml"));
  testing::WriteText(dir + "/identify.yaml", job);
  run("run " + dir + "/identify.yaml -o " + dir + "/result");

  const nlohmann::json result =
      nlohmann::json::parse(testing::ReadText(dir + "/result/result.json"));
  const WorkcellEvaluation evaluation =
      EvaluateWorkcell(result, ReadTruth(rec + "/truth.yaml"), rec + "/truth.yaml");
  int checked = 0;
  for (const auto& q : evaluation.quantities) {
    EXPECT_LT(std::abs(q.normalized()), 3.0)
        << q.name << " error " << q.error << " " << q.unit << ", sigma " << q.sigma;
    if (q.name.rfind("tool.", 0) == 0) {
      EXPECT_LT(std::abs(q.error), q.unit == "mm" ? 0.5 : 1.5e-3) << q.name;  // and useful
    }
    ++checked;
  }
  EXPECT_EQ(checked, 24);  // base, tool, two cameras: 6 each
}

}  // namespace
}  // namespace cellmetry
