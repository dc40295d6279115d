// The result's description of a cell's estimate (internal to the cell layer): every frame,
// model and effect parameter with its sigma and the sigma's parts, whether it was held and
// whether a hold decides it, and the robot models and effects as fitted.
#pragma once

#include <set>
#include <string>

#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/cell/workcell_result.h"

namespace cellmetry {

// Adds `result`'s estimate, uncertainty and unidentifiable parameters as the result reports
// them: its frames (each base, carried target and camera), its model and effect parameters
// (`held`: the parameters held, HeldOf the unidentifiable), its robot models at the fitted
// values and its effect models.
void DescribeEstimate(const WorkcellProblem& spec, const std::set<std::string>& held,
                      WorkcellResult* result);

}  // namespace cellmetry
