// Every cell topology identifies its truth or is refused in words, never a crash. One or two
// UR3s, one to four static cameras above them, with and without a world target, with and
// without starts in the job (cameras, and a second robot's base), the carried boards' rotation
// used or not, a camera riding on the first robot's flange (eye in hand) or not: 128 cells
// simulated with noise and identified. Over some 1,800 fitted base,
// camera and tool coordinates a 3-sigma miss is likely by chance, so each is held to 4.5 sigma,
// the share beyond 3 sigma to 2 %, and their RMS in sigmas to 0.8-1.25 (sigma honest); a
// refused cell must say what to do. Without a world target the first robot's base is the
// world, held where the simulation put it, and a second robot is placed through the cameras. A
// camera on the flange needs the board it sees to be the world: without a world target those
// cells are refused in words.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

struct Topology {
  int robots = 1;
  int cameras = 1;
  bool world_target = true;
  bool starts = false;
  bool tool_rotation = true;
  bool wrist = false;  // a camera `wrist` rides on ur3_0's flange
};

std::string Name(const Topology& t) {
  std::ostringstream name;
  name << t.robots << (t.robots == 1 ? " robot, " : " robots, ") << t.cameras
       << (t.cameras == 1 ? " camera, " : " cameras, ")
       << (t.world_target ? "world target" : "no world target") << (t.starts ? ", starts" : "")
       << (t.tool_rotation ? ", tool rotation" : "") << (t.wrist ? ", camera on the robot" : "");
  return name.str();
}

// Two UR3s a metre apart and four cameras 2.5 m above the floor looking down at them.
const char* kBases[] = {"{xyz: [0, 0, 0], rvec: [0, 0, 0.1]}",
                        "{xyz: [900, 100, 0], rvec: [0, 0, 2.0]}"};
const char* kBaseTruth = "xyz: [0, 0, 0], rvec: [0, 0, 0.1]";  // the first robot's
const char* kCameras[] = {"{xyz: [-300, -700, 2500], rvec: [3.1, -0.12, 0]}",
                          "{xyz: [1200, -700, 2500], rvec: [3.1, 0.12, 0]}",
                          "{xyz: [-300, 800, 2500], rvec: [3.0, -0.1, 0.1]}",
                          "{xyz: [1200, 800, 2500], rvec: [3.0, 0.1, -0.1]}"};
// Starts as a user would give them: 20 mm and 0.03 rad off.
const char* kCameraStarts[] = {"{xyz: [-280, -690, 2520], rvec: [3.12, -0.1, 0.02]}",
                               "{xyz: [1220, -690, 2480], rvec: [3.08, 0.15, 0]}",
                               "{xyz: [-310, 780, 2510], rvec: [3.02, -0.08, 0.12]}",
                               "{xyz: [1180, 820, 2490], rvec: [2.98, 0.12, -0.07]}"};

// The camera on ur3_0's flange (T_flange_camera), and a start 20 mm and 0.03 rad off.
const char* kWrist = "{xyz: [1, 60, 40], rvec: [0.1, -0.05, 0.3]}";
const char* kWristStart = "{free: all, xyz: [15, 75, 30], rvec: [0.12, -0.03, 0.32]}";

std::string Simulation(const Topology& t) {
  std::string yaml = "simulation: workcell\nseed: 11\nrepeats: 1\nworld_target: " +
                     std::string(t.world_target ? "world" : "none") + "\nrobots:\n";
  for (int r = 0; r < t.robots; ++r) {
    const std::string i = std::to_string(r);
    yaml += "  ur3_" + i + ":\n    model: " + testing::Source("configs/robots/ur3_vsb2020.yaml") +
            "\n    base: " + kBases[r] + "\n    tools: {tool_" + i +
            ": {xyz: [0.5, -0.3, 66], rvec: [0.01, 0.02, -0.01]}}\n" +
            (t.wrist && r == 0 ? "    cameras: {wrist: " + std::string(kWrist) + "}\n" : "") +
            "    poses: {random: 40, lower: [-3.1, -2.8, -2.6, -3.1, -3.1, -3.1], "
            "upper: [3.1, -0.3, 2.6, 3.1, 3.1, 3.1]}\n";
  }
  yaml += "cameras:\n";
  for (int c = 0; c < t.cameras; ++c) {
    yaml += "  cam" + std::to_string(c + 1) + ": " + kCameras[c] + "\n";
  }
  return yaml + "noise: {position_mm: [0.05, 0.05, 0.2], rotation_rad: [0.0005, 0.0005, 0.001]}\n";
}

std::string Job(const Topology& t, const std::string& dir) {
  std::string yaml = "job: workcell\nrecording: " + dir + "/rec\noutput: " + dir + "/fit\n" +
                     "world_target: " + (t.world_target ? "world" : "none") + "\n" +
                     "use_tool_rotation: " + (t.tool_rotation ? "true" : "false") + "\nrobots:\n";
  for (int r = 0; r < t.robots; ++r) {
    const std::string i = std::to_string(r);
    std::string base = "{free: all}";
    if (!t.world_target && r == 0) base = "{free: none, start: {" + std::string(kBaseTruth) + "}}";
    if (t.starts && r == 1) {
      base = "{free: all, start: {xyz: [880, 130, 20], rvec: [0, 0.02, 1.97]}}";
    }
    yaml += "  ur3_" + i + ":\n    model: " + testing::Source("configs/robots/ur3_vsb2020.yaml") +
            "\n    base: " + base + "\n    tools:\n      tool_" + i +
            ": {free: " + (t.tool_rotation ? "all" : "[x, y, z]") + "}\n";
    if (t.wrist && r == 0) {
      yaml += "    cameras:\n      wrist: " + std::string(t.starts ? kWristStart : "{free: all}") +
              "\n";
    }
  }
  yaml += "noise:\n  cameras:\n";
  for (int c = 0; c < t.cameras; ++c) {
    yaml += "    cam" + std::to_string(c + 1) +
            ": {position_mm: [0.05, 0.05, 0.2], rotation_rad: [0.0005, 0.0005, 0.001]}\n";
  }
  if (t.wrist) {
    yaml += "    wrist: {position_mm: [0.05, 0.05, 0.2], rotation_rad: [0.0005, 0.0005, 0.001]}\n";
  }
  if (t.starts) {
    yaml += "cameras:\n";
    for (int c = 0; c < t.cameras; ++c) {
      yaml += "  cam" + std::to_string(c + 1) + ": " + kCameraStarts[c] + "\n";
    }
  }
  return yaml + "solver: {type: ceres_lm}\nvalidation: {folds: 0, leave_one_camera_out: false}\n";
}

// How far each free coordinate of `fitted` lies from `truth`, in its sigmas (held ones left out).
void AddDeviations(const FrameEstimate& fitted, const Pose& truth, std::vector<double>* out) {
  const Eigen::Vector3d turn = RvecFromRotation(fitted.pose.R * truth.R.transpose());
  for (int i = 0; i < 3; ++i) {
    if (!fitted.held[i] && fitted.sigma_mm[i] > 0) {
      out->push_back(std::abs(fitted.pose.t[i] - truth.t[i]) / fitted.sigma_mm[i]);
    }
    if (!fitted.held[3 + i] && fitted.sigma_rad[i] > 0) {
      out->push_back(std::abs(turn[i]) / fitted.sigma_rad[i]);
    }
  }
}

TEST(CellTopologies, EveryCellIdentifiesItsTruthOrIsRefusedInWords) {
  std::vector<double> deviations;
  std::vector<double> wrist_deviations;  // the cameras on a flange alone
  int identified = 0, refused = 0;
  std::string refusals;
  for (int robots = 1; robots <= 2; ++robots) {
    for (int cameras = 1; cameras <= 4; ++cameras) {
      for (bool world_target : {true, false}) {
        for (bool starts : {false, true}) {
          for (bool tool_rotation : {true, false}) {
            for (bool wrist : {false, true}) {
              const Topology t{robots, cameras, world_target, starts, tool_rotation, wrist};
              SCOPED_TRACE(Name(t));
              const std::string dir = testing::TempDirForThisTest(
                  "cell_topologies/" + std::to_string(robots) + std::to_string(cameras) +
                  std::to_string(world_target) + std::to_string(starts) +
                  std::to_string(tool_rotation) + std::to_string(wrist));
              testing::WriteText(dir + "/sim.yaml", Simulation(t));
              const WorkcellSimulationSpec spec =
                  LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
              const Recording recording = SimulateWorkcell(spec, nullptr);
              testing::WriteText(dir + "/job.yaml", Job(t, dir));
              try {
                const WorkcellJob job = LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(),
                                                        /*recording_must_exist=*/false);
                ValidateJobAgainstRecording(job, recording);
                const WorkcellResult result = testing::Identify(job, recording);
                ++identified;
                std::vector<double> cell;
                for (const auto& robot : spec.robots) {
                  AddDeviations(testing::Frame(result, robot.name + ".base"), robot.T_world_base,
                                &cell);
                  for (const auto& [target, T_flange_target] : robot.T_flange_target) {
                    AddDeviations(testing::Frame(result, target), T_flange_target, &cell);
                  }
                  for (const auto& [camera, T_flange_camera] : robot.T_flange_camera) {
                    const size_t before = cell.size();
                    AddDeviations(testing::Frame(result, robot.name + "." + camera),
                                  T_flange_camera, &cell);
                    wrist_deviations.insert(wrist_deviations.end(), cell.begin() + before,
                                            cell.end());
                  }
                }
                for (const auto& [camera, T_world_cam] : spec.T_world_cam) {
                  AddDeviations(testing::Frame(result, camera), T_world_cam, &cell);
                }
                for (double d : cell) EXPECT_LT(d, 4.5) << "a coordinate " << d << " sigma off";
                deviations.insert(deviations.end(), cell.begin(), cell.end());
              } catch (const InputError& e) {
                ++refused;
                EXPECT_FALSE(e.hint().empty()) << "refused without what to do: " << e.message();
                // Only a camera on the flange without the board it needs as the world.
                if (!(wrist && !world_target)) refusals += Name(t) + ": " + e.message() + "\n";
              }
            }
          }
        }
      }
    }
  }
  int beyond = 0;
  for (double d : deviations) beyond += d > 3.0;
  EXPECT_LT(beyond, 0.02 * static_cast<double>(deviations.size()))
      << beyond << " of " << deviations.size() << " coordinates beyond 3 sigma";
  EXPECT_EQ(identified + refused, 128);
  // Each camera sees each board from above: every cell is identified but those with a camera on
  // the flange and no world target (32), refused because the board it sees must be the world.
  EXPECT_EQ(refused, 32) << refusals;
  EXPECT_TRUE(refusals.empty()) << refusals;
  // And sigma is honest: the deviations' RMS in sigmas is 1 (1.00 when written).
  double squares = 0.0;
  for (double d : deviations) squares += d * d;
  const double rms = std::sqrt(squares / static_cast<double>(deviations.size()));
  EXPECT_GT(rms, 0.8);
  EXPECT_LT(rms, 1.25);
  std::cerr << identified << " cells identified, " << deviations.size()
            << " coordinates checked: RMS " << rms << " sigma, " << beyond << " beyond 3 sigma\n";
  double wrist_squares = 0.0, wrist_max = 0.0;
  for (double d : wrist_deviations) {
    wrist_squares += d * d;
    wrist_max = std::max(wrist_max, d);
  }
  EXPECT_EQ(wrist_deviations.size(), 32u * 6u);  // every identified cell's camera on the flange
  std::cerr << "cameras on a flange: " << wrist_deviations.size() << " coordinates, RMS "
            << std::sqrt(wrist_squares / static_cast<double>(wrist_deviations.size()))
            << " sigma, largest " << wrist_max << " sigma\n";
}

}  // namespace
}  // namespace cellmetry
