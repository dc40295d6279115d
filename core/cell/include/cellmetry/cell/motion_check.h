// Whether the poses a fit uses move its robots: the checks that catch a recording whose joints
// say nothing (every capture at one command, an encoder that never changes) before the fit reads
// numbers into it.
//
//   CheckRobotsMove  a robot whose every used sample has the same joint readings, while the job
//                    frees its base, tools or model, is an InputError at samples.csv: base, tool
//                    and model then move together, and the fit would return its start.
//   StillJoints      a joint whose reading never changes over the used samples while other
//                    joints move: a warning each. Its geometry cannot be told from its
//                    neighbours', and a reading that never changes is more often a stuck encoder
//                    than a plan.
//
// "Never changes": all readings within kStillJointRad of each other (0.0001 rad: repeated
// captures of one command read within an encoder's noise, a millionth of a turn, far below it;
// any pose a plan asks for moves a joint by far more).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

inline constexpr double kStillJointRad = 1e-4;

void CheckRobotsMove(const WorkcellProblem& spec, const Recording& recording,
                     const WorkcellData& data);

std::vector<std::string> StillJoints(const WorkcellProblem& spec, const Recording& recording,
                                     const WorkcellData& data);

}  // namespace cellmetry
