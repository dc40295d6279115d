// `compare: hand_eye`: cellmetry's fit of a hand-eye cell against OpenCV's closed-form hand-eye
// methods on the same simulated, noisy data, over seeds, with intervals and a recommendation.
//
// The cell is one robot and one camera. Eye-to-hand: the camera is static and sees a board on the
// robot's tool, with no world board (`world_target: none`: the robot's base is the world); the
// answer is the camera in the base frame, T_base_cam. Eye-in-hand: the camera rides on the flange
// and sees a static board; the answer is T_flange_cam. Each seed draws fresh noise; every method
// gets the same captures: the measured board poses in the camera (T_cam_board, the recording's
// observations with rotation) and the robot's flange poses from the nominal model at the
// recorded joints (T_base_flange(q)).
//
// Methods:
//   cellmetry                     the job's fit (closed-form start, least squares, weighted by
//                                 the noise model), timed as a whole (start, solve, covariance)
//   opencv_tsai, _park, _horaud,  cv::calibrateHandEye (AX = XB from pairs of motions: Tsai and
//   _andreff, _daniilidis         Lenz 1989, Park and Martin 1994, Horaud and Dornaika 1995,
//                                 Andreff et al. 1999, Daniilidis 1999)
//   opencv_shah, opencv_li        cv::calibrateRobotWorldHandEye (AX = ZB from the captures
//                                 themselves: Shah 2013, Li et al. 2010)
//
// Scores per seed: the hand-eye frame's position error (mm) and rotation error (mrad, the angle
// of R_found R_truth^T) against the simulation's truth, and the method's time.
//
// Spec (YAML):
//   compare: hand_eye
//   description: free text
//   simulation: <simulation spec>   # the cell and its truth; noise drawn per seed (one robot,
//                                   # one camera: on its flange with a world board, or static
//                                   # with a board on the tool and world_target: none)
//   job: <job file>                 # cellmetry's fit of it (its recording is not read)
//   seeds: 10
//   output: <folder for table.md, table.csv and report.html>
#pragma once

#include <string>
#include <vector>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell_simulation.h"

namespace cellmetry {

enum class HandEyeSetup { kEyeToHand, kEyeInHand };
std::string HandEyeSetupName(HandEyeSetup setup);  // "eye-to-hand", "eye-in-hand"

struct HandEyeCompareSpec {
  std::string file;
  std::string description;
  WorkcellSimulationSpec simulation;
  WorkcellJob job;
  // Read from the simulation: the setup, its one robot, camera and board.
  HandEyeSetup setup = HandEyeSetup::kEyeToHand;
  std::string robot, camera, board;
  int seeds = 10;
  std::string output;
};

struct HandEyeCompareRow {
  std::string method;
  std::vector<double> position_error_mm;  // per seed
  std::vector<double> rotation_error_mrad;
  std::vector<double> time_s;
  int failed = 0;  // seeds whose method gave no answer (not finite)
};

HandEyeCompareSpec LoadHandEyeCompare(const std::string& path, Registry& registry);
// One row per method, cellmetry first. With a `checkpoint` path, each finished seed is kept
// there and a seed found there is not run again (checkpoint.h).
std::vector<HandEyeCompareRow> RunHandEyeCompare(const HandEyeCompareSpec& spec,
                                                 const std::string& checkpoint = "");
// One line per score (position, rotation): which method, with intervals.
std::vector<std::string> HandEyeRecommendations(const std::vector<HandEyeCompareRow>& rows);
std::string HandEyeCompareMarkdown(const HandEyeCompareSpec& spec,
                                   const std::vector<HandEyeCompareRow>& rows);
std::string HandEyeCompareCsv(const std::vector<HandEyeCompareRow>& rows);

}  // namespace cellmetry
