// The eye-to-hand cell: one static camera, a board on the robot's tool, no world target and no
// camera start. The robot's base is the world; the camera and the tool offset are found from a
// closed-form start (tools and camera in turn) and come back within 3 sigma of the truth.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

TEST(EyeToHand, OneStaticCameraWithoutAWorldTargetFindsTheCameraInTheBaseFrame) {
  const std::string dir = testing::TempDirForThisTest("eye_to_hand");
  testing::WriteText(dir + "/sim.yaml",
                     "simulation: workcell\nseed: 3\nrepeats: 1\nrobots:\n  ur3:\n    model: " +
                         testing::Source("configs/robots/ur3_vsb2020.yaml") +
                         "\n    base: {xyz: [431, 555, -460], rvec: [0.01, -0.02, 0.4]}\n"
                         "    tools:\n      tool: {xyz: [3, -2, 66], rvec: [0, 0, 0]}\n"
                         "    poses: {from_recording: " +
                         testing::Source("tests/data/vsb/sim_b") +
                         "}\ncameras:\n"
                         "  cam1: {xyz: [745, 290, 986], rvec: [-2.6081, -1.2675, 0.5875]}\n"
                         "noise:\n  position_mm: [0.3, 0.3, 1.0]\n"
                         "  rotation_rad: [0.002, 0.002, 0.004]\n");
  const WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
  Recording recording = SimulateWorkcell(spec, nullptr);
  // No world target: only the board on the tool is seen.
  std::vector<Observation> tool_only;
  for (const auto& obs : recording.observations) {
    if (obs.target == "tool") tool_only.push_back(obs);
  }
  recording.observations = tool_only;
  recording.targets.erase("world");
  testing::WriteText(dir + "/job.yaml", "job: workcell\nrecording: " + dir + "\noutput: " + dir +
                                            "/fit\n"
                                            "world_target: none\nrobots:\n  ur3:\n    model: " +
                                            testing::Source("configs/robots/ur3_vsb2020.yaml") +
                                            "\n    tools:\n      tool: {free: [x, y, z]}\n"
                                            "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n");
  const WorkcellJob job =
      LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), /*recording_must_exist=*/false);
  const WorkcellResult r = testing::Identify(job, recording);
  const Pose T_base_cam = spec.robots[0].T_world_base.inverse() * spec.T_world_cam.at("cam1");
  const FrameEstimate& camera = testing::Frame(r, "cam1");
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(camera.pose.t[i] - T_base_cam.t[i]), 3 * camera.sigma_mm[i])
        << "cam1 "
        << "xyz"[i] << " = " << camera.pose.t[i] << " +- " << camera.sigma_mm[i] << ", truth "
        << T_base_cam.t[i];
  }
  const Eigen::Vector3d turn = RvecFromRotation(camera.pose.R * T_base_cam.R.transpose());
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(turn[i]), 3 * camera.sigma_rad[i]) << i;
  const FrameEstimate& tool = testing::Frame(r, "tool");
  const Eigen::Vector3d tool_truth(3, -2, 66);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(tool.pose.t[i] - tool_truth[i]), 3 * tool.sigma_mm[i]) << "xyz"[i];
  }
}

}  // namespace
}  // namespace cellmetry
