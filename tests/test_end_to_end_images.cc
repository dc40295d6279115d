// End to end from pixels: a rendered stereo recording of the delta arm goes through
// `cellmetry simulate` (images), `detect` (the white-dot plugin) and `run` (kinematic
// calibration), and the arm's identifiable dimensions land within 3 sigma of the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cellmetry/workcell_simulation.h"
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
  const std::string detect = testing::ReplaceOnce(
      testing::ReadText(testing::Source("configs/jobs/delta_detect.yaml")),
      "recording: ../../results/delta_images", "recording: " + rec);
  testing::WriteText(dir + "/detect.yaml",
                     testing::ReplaceOnce(detect, "../cameras/oakd_like.yaml",
                                          testing::Source("configs/cameras/oakd_like.yaml")));
  run("detect " + dir + "/detect.yaml");
  std::string job = testing::ReadText(testing::Source("configs/jobs/delta_calibration_images.yaml"));
  job = testing::ReplaceOnce(job, "recording: ../../results/delta_images", "recording: " + rec);
  job = testing::ReplaceOnce(job, "model: ../robots/delta.yaml",
                             "model: " + testing::Source("configs/robots/delta.yaml"));
  testing::WriteText(dir + "/calibrate.yaml", job);
  run("run " + dir + "/calibrate.yaml -o " + dir + "/result");

  const nlohmann::json result = nlohmann::json::parse(testing::ReadText(dir + "/result/result.json"));
  const WorkcellTruth truth = ReadTruth(rec + "/truth.yaml");
  std::map<std::string, std::pair<double, double>> estimate;  // name -> value, sigma
  for (const auto& p : result["model_parameters"]) {
    estimate[p["name"].get<std::string>()] = {p["value"].get<double>(), p["sigma"].get<double>()};
  }
  ASSERT_EQ(estimate.size(), 15u);
  for (int arm = 1; arm <= 3; ++arm) {
    const std::string a = "arm" + std::to_string(arm) + ".";
    auto t = [&](const std::string& name) { return truth.model.at("delta.model." + a + name); };
    // R - r: r is held at nominal, so R carries the difference.
    const double diff_error = (estimate[a + "R"].first - estimate[a + "r"].first) - (t("R") - t("r"));
    EXPECT_LT(std::abs(diff_error), 3 * estimate[a + "R"].second) << a << "R-r";
    for (const std::string name : {"L", "l", "homing"}) {
      const auto [value, sigma] = estimate[a + name];
      EXPECT_LT(std::abs(value - t(name)), 3 * sigma) << a << name << " sigma " << sigma;
    }
  }
}

}  // namespace
}  // namespace cellmetry
