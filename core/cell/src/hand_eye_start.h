// The closed-form start of a camera riding on a robot's flange (eye in hand).
//
// The camera sees the world target (the board that defines the world) from every pose i:
//
//   T_world_base * F_i * X = C_i      F_i = T_base_flange(q_i) at the nominal model,
//                                     X = T_flange_camera, C_i = T_world_cam_i = M_i^-1,
//                                     M_i the measured T_cam_world (the board in the camera).
//
// Between two poses i, j the base drops out: A X = X B with A = F_i^-1 F_j (the flange's
// motion) and B = M_i M_j^-1 (the camera's), the hand-eye equation. SolveHandEye solves it by
// Park & Martin (1994), "Robot sensor calibration: solving AX = XB on the Euclidean group", IEEE
// Trans. Robotics and Automation 10(5), 717-721: the rotation axes satisfy alpha_k = R_X beta_k
// (alpha = Log R_A, beta = Log R_B), so R_X = (M^T M)^(-1/2) M^T with M = sum beta_k alpha_k^T
// (their least-squares rotation, here through the SVD of M = U S V^T as V U^T, which also keeps
// det R_X = +1); then t_X is the least-squares solution of (R_A - I) t_X = R_X t_B - t_A stacked
// over the motions (their translation step).
// HandEyeStart then places the base: T_world_base = C_i X^-1 F_i^-1, averaged over the poses.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// X from motion pairs (A_k, B_k) with A_k X = X B_k; none when the rotation axes are all
// parallel (a turn about one axis leaves X's translation along it and R_X about it free).
std::optional<Pose> SolveHandEye(const std::vector<Pose>& A, const std::vector<Pose>& B);

// Each camera riding on a robot's flange whose start the job does not give: X by SolveHandEye
// over pairs of its captures; and, where the robot carries no start of its own, the robot's base
// from the same captures. Raises InputError when a camera saw the world target from fewer than
// three poses or the flange turned about one axis only.
void HandEyeStart(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
                  WorkcellEstimate* estimate);

}  // namespace cellmetry
