// Where a held-out check's poses go beyond the joint ranges the calibration's poses span.
//
// A model fitted on poses is measured inside their ranges. Beyond them, what the model leaves
// out (a compliance growing with a load the calibration never applied, a gear error over angles
// it never turned through) is extrapolated with it, and a point's predicted sigma, which holds
// only what the model contains, need not cover its error. A held-out RMS mixes the two; the
// score is split at that line so that a user sees which one they are reading.
//
// A joint's range is the interval of its readings over the calibration's samples; a scored pose
// is beyond when any joint of its robot reads outside its range (JointsOutsideRanges,
// basics/joint_range.h, the rule compensation marks commands by).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/joint_range.h"
#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

struct JointRange {
  std::string robot;
  int joint = 0;  // 1-based
  double min_rad = 0.0;
  double max_rad = 0.0;
};

// Every joint's range over `recording`'s samples: robots in name order, joints 1..n. A robot
// without samples has no ranges.
std::vector<JointRange> JointRanges(const Recording& recording);

// Records in each of `result`'s robot models the joint ranges of `recording`, the recording it
// was fitted on (RobotModelRecord::joint_ranges_rad).
void RecordJointRanges(const Recording& recording, WorkcellResult* result);

// Marks each of `score`'s points whose sample (in `held_out`) has a joint beyond `calibration`'s
// ranges, and fills the score's summary of them (HeldOutSetupScore::beyond_calibration): each
// joint some scored pose goes beyond, the poses beyond, and the RMS within and beyond.
void MarkBeyondCalibration(const Recording& calibration, const Recording& held_out,
                           HeldOutSetupScore* score);

// Fills `score`'s poses beyond the joint ranges `result` was fitted on
// (RobotModelRecord::joint_ranges_rad) from `rows`, the answer's position rows on `fresh`, and
// the RMS there and within (RecordingScore). A result that records no ranges marks none.
void MarkBeyondCalibration(const WorkcellResult& result, const Recording& fresh,
                           const std::vector<ResidualRow>& rows, RecordingScore* score);

// In words, for a report: how many scored poses go beyond, each joint's scored and calibrated
// ranges (deg), and the RMS beyond and within. "" when no scored pose goes beyond.
std::string BeyondCalibrationText(const HeldOutSetupScore& score);

// The same for a validation recording's score; "" when no pose goes beyond.
std::string BeyondCalibrationText(const RecordingScore& score);

}  // namespace cellmetry
