// The uncertain inputs' link (core/cell/src/input_uncertainty.h) is made in the parameters of the
// fit it is combined with. A fit's frames turn about the rotations it was assembled at
// (frame_block.h), so its rotation parameters depend on that start; its translations do not,
// and neither may their sigma from the inputs. Here one simulated UR3 cell (two static cameras,
// uncertain focal lengths and kinematic table) is fitted from its closed-form start and from a
// start whose base and cameras are turned by 30 mrad: both reach the same answer, and every
// translation's sigma from the inputs agrees. (Linked at the answer's rotations while the
// covariance was over the start's, as before, the base's sigma from the inputs moved by 15-46 %
// and the tool's y by 65 % between the two starts: checked.)
#include <gtest/gtest.h>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_initial.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "fit_once.h"
#include "input_uncertainty.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

struct Linked {
  Uncertainty uncertainty;
  WorkcellEstimate answer;
};

TEST(InputLink, ATranslationsSigmaFromTheInputsDoesNotDependOnTheFitsStart) {
  const std::string dir = testing::TempDirForThisTest("input_link");
  std::string sim = testing::ReadText(testing::Source("configs/simulations/ur3_two_cameras.yaml"));
  sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  sim = testing::ReplaceOnce(sim, "../../tests/data/vsb/sim_b",
                             testing::Source("tests/data/vsb/sim_b"));
  testing::WriteText(dir + "/sim.yaml", sim);
  const Recording recording =
      SimulateWorkcell(LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins()), nullptr);
  testing::WriteText(
      dir + "/job.yaml",
      "job: workcell\nrecording: " + dir + "/none\nrobots:\n  ur3:\n    model: " +
          testing::Source("configs/robots/ur3_vsb2020.yaml") +
          "\n    base: {free: all}\n    tools:\n      tool: {free: [x, y, z]}\n" +
          testing::kTwoCameraNoiseYaml +
          "uncertain_inputs:\n  effects:\n    - {sigma: 0.005, effect: {type: camera_intrinsics, "
          "cameras: [cam1, cam2], terms: [focal]}}\n  robot_model: {mm: 0.1, rad: 0.0002}\n"
          "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n");
  const WorkcellJob job = LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), false);
  const WorkcellProblem& spec = job.problem;
  const WorkcellData data = PrepareWorkcellData(spec, recording);
  const NoiseModel noise = BuildNoiseModel(recording, spec.noise);

  auto fit_from = [&](const WorkcellEstimate& start) {
    Fit fit = FitOnce(spec, recording, data, noise, start, {}, {}, testing::JobSolver(job));
    Linked out;
    out.uncertainty = ComputeUncertainty(fit.assembled->problem);
    InputLinker linker(spec, recording, data, noise, start);
    AddInputUncertainty(linker.LinkAt(AnswerOf(*fit.assembled)), &out.uncertainty);
    out.answer = ReadEstimate(spec, *fit.assembled);
    return out;
  };
  const WorkcellEstimate closed_form = InitialEstimate(spec, recording, data);
  WorkcellEstimate turned = closed_form;
  const double rvec[3] = {0.03, -0.02, 0.01};  // 37 mrad
  for (auto& [name, T] : turned.T_world_base) T.R = RotationFromRvec(rvec) * T.R;
  for (auto& [name, T] : turned.T_world_cam) T.R = RotationFromRvec(rvec) * T.R;
  const Linked a = fit_from(closed_form);
  const Linked b = fit_from(turned);

  ASSERT_EQ(a.uncertainty.names, b.uncertainty.names);
  EXPECT_LT((a.answer.T_world_base.at("ur3").t - b.answer.T_world_base.at("ur3").t).norm(), 1e-6);
  int translations = 0;
  for (size_t i = 0; i < a.uncertainty.names.size(); ++i) {
    const std::string& name = a.uncertainty.names[i];
    const char axis = name.back();
    if (name.size() < 2 || name[name.size() - 2] != '.' ||
        (axis != 'x' && axis != 'y' && axis != 'z')) {
      continue;
    }
    ++translations;
    const double sigma_a = a.uncertainty.sigma_inputs[static_cast<Eigen::Index>(i)];
    const double sigma_b = b.uncertainty.sigma_inputs[static_cast<Eigen::Index>(i)];
    EXPECT_GT(sigma_a, 0.0) << name;
    EXPECT_NEAR(sigma_b, sigma_a, 1e-6 * sigma_a + 1e-12) << name;
  }
  EXPECT_GE(translations, 9);  // the base's, the tool's and two cameras'
}

}  // namespace
}  // namespace cellmetry
