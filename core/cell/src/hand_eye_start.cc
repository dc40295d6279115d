// The closed-form start of a camera riding on a flange (hand_eye_start.h).
#include "hand_eye_start.h"

#include <Eigen/Dense>
#include <algorithm>
#include <map>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

// One pose's flange and measured board: F_i and M_i (hand_eye_start.h).
struct HandEyePose {
  Pose T_base_flange;
  Pose T_cam_world;
};

Pose Measured(const Observation& obs) {
  return Pose{RotationFromRvec(obs.rvec->data()), obs.position_mm};
}

// A camera's captures, one per commanded pose (repeated captures add no motion).
std::vector<HandEyePose> PosesOf(const WorkcellProblem& spec, const Recording& recording,
                                 const WorkcellData& data, int robot, int tool,
                                 const std::vector<double>& model) {
  std::vector<HandEyePose> poses;
  std::map<int, bool> seen;  // pose id
  for (const ToolMeasurement& m : data.tools) {
    if (m.robot != robot || m.tool != tool) continue;
    const Sample& sample = recording.samples[m.sample_index];
    if (seen[sample.pose]) continue;
    seen[sample.pose] = true;
    HandEyePose p;
    if (!spec.robots[robot].model->Forward(sample.q.data(), model.data(), &p.T_base_flange)) {
      continue;
    }
    p.T_cam_world = Measured(recording.observations[m.observation]);
    poses.push_back(p);
  }
  return poses;
}

// Motion pairs between poses: every pair among at most 40 poses spread over the run (pairs far
// apart turn more, which the rotation axes need; 780 pairs are plenty for a start).
void MotionPairs(const std::vector<HandEyePose>& poses, std::vector<Pose>* A,
                 std::vector<Pose>* B) {
  const size_t n = poses.size();
  const size_t step = std::max<size_t>(1, (n + 39) / 40);
  for (size_t i = 0; i < n; i += step) {
    for (size_t j = i + step; j < n; j += step) {
      A->push_back(poses[i].T_base_flange.inverse() * poses[j].T_base_flange);
      B->push_back(poses[i].T_cam_world * poses[j].T_cam_world.inverse());
    }
  }
}

InputError TooFewMotions(const Recording& recording, const std::string& camera,
                         const std::string& why) {
  return InputError({recording.folder + "/observations.csv", 0, 0},
                    "camera '" + camera + "' on the flange cannot be placed: " + why,
                    "Record the world target from at least three poses whose flange turns "
                    "about two different axes");
}

}  // namespace

std::optional<Pose> SolveHandEye(const std::vector<Pose>& A, const std::vector<Pose>& B) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < A.size(); ++k) {
    M += RvecFromRotation(B[k].R) * RvecFromRotation(A[k].R).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d& s = svd.singularValues();
  // Two independent axes determine R_X (the third follows); one does not.
  if (!(s[1] > 1e-6 * s[0])) return std::nullopt;
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  Pose X;
  X.R = svd.matrixV() * D * svd.matrixU().transpose();
  Eigen::MatrixXd lhs(3 * A.size(), 3);
  Eigen::VectorXd rhs(3 * A.size());
  for (size_t k = 0; k < A.size(); ++k) {
    lhs.block<3, 3>(3 * k, 0) = A[k].R - Eigen::Matrix3d::Identity();
    rhs.segment<3>(3 * k) = X.R * B[k].t - A[k].t;
  }
  X.t = lhs.colPivHouseholderQr().solve(rhs);
  return X;
}

void HandEyeStart(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
                  WorkcellEstimate* estimate) {
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    const WorkcellRobot& robot = spec.robots[r];
    for (size_t t = 0; t < robot.tools.size(); ++t) {
      const WorkcellTool& tool = robot.tools[t];
      if (!tool.is_camera()) continue;
      const auto poses = PosesOf(spec, recording, data, static_cast<int>(r), static_cast<int>(t),
                                 estimate->model.at(robot.name));
      if (poses.size() < 3) {
        throw TooFewMotions(
            recording, tool.camera,
            "it saw the world target from " + std::to_string(poses.size()) + " poses");
      }
      Pose X = tool.flange_tool.start;
      if (!tool.start_given) {
        std::vector<Pose> A, B;
        MotionPairs(poses, &A, &B);
        const auto solved = SolveHandEye(A, B);
        if (!solved) {
          throw TooFewMotions(recording, tool.camera, "the flange turned about one axis only");
        }
        X = *solved;
        estimate->T_flange_target[tool.target] = X;
      }
      if (robot.base_start) estimate->T_world_base[robot.name] = *robot.base_start;
      if (estimate->T_world_base.count(robot.name)) continue;
      std::vector<Eigen::Matrix3d> rotations;
      Eigen::Vector3d t_sum = Eigen::Vector3d::Zero();
      for (const HandEyePose& p : poses) {
        const Pose T_world_base = p.T_cam_world.inverse() * X.inverse() * p.T_base_flange.inverse();
        rotations.push_back(T_world_base.R);
        t_sum += T_world_base.t;
      }
      estimate->T_world_base[robot.name] =
          Pose{MeanRotation(rotations), t_sum / static_cast<double>(poses.size())};
    }
  }
}

}  // namespace cellmetry
