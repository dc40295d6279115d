// A start the job gives that lies far from where the data put the frame.
//
// A frame's start from the job (`base: {start: ...}`, a camera's `start:`) replaces the closed
// form (workcell_initial.h). A start in another basin than the data's — a base given 99 m off —
// converges to a wrong minimum at exit 0. So where the closed form can be found without the
// job's starts, each started frame that the fit frees is compared with it (a held frame's start
// is its value); a start more than kFarStartMm or
// kFarStartRad away is far, and IdentifyWorkcell then fits from both and keeps the one that
// predicts the carried targets better, saying so in the result's warnings.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// Far: beyond any cell's measuring error, within a room.
inline constexpr double kFarStartMm = 1000.0;
inline constexpr double kFarStartRad = 0.5;

struct FarStart {
  std::string frame;       // "ur3.base", "cam1"
  double distance_mm = 0;  // between the given start and the closed form's
  double angle_rad = 0;
};

// The started frames lying far from the closed form's start, and in `without_starts` the
// problem with every start removed (the closed form's). Empty when none is far, or when the
// closed form needs the starts (it raises without them: fewer than three usable measurements,
// a robot placed only through its start).
std::vector<FarStart> FarStarts(const WorkcellProblem& spec, const Recording& recording,
                                WorkcellProblem* without_starts);

}  // namespace cellmetry
