// Predictions of a carried target and their Cramer-Rao floor (prediction.h).
#include "cellmetry/cell/prediction.h"

#include <set>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/cell/workcell_assembly.h"

namespace cellmetry {
namespace {

// A recording of `commands` with a zero measurement of the target for each: assembled with unit
// sigma, its residuals are the predictions and its Jacobian is theirs.
Recording PredictionRecording(const PredictedTarget& what, int joints,
                              const std::vector<std::vector<double>>& commands) {
  Recording r;
  r.folder = "(validation commands)";
  r.robots[what.robot] = joints;
  r.cameras = {what.camera};
  r.targets[what.target] = what.robot;
  for (size_t i = 0; i < commands.size(); ++i) {
    Sample s;
    s.id = static_cast<int>(i);
    s.pose = static_cast<int>(i);
    s.robot = what.robot;
    s.q = commands[i];
    r.samples.push_back(s);
    Observation obs;
    obs.sample = s.id;
    obs.camera = what.camera;
    obs.target = what.target;
    obs.position_mm = Eigen::Vector3d::Zero();
    r.observations.push_back(obs);
  }
  return r;
}

// The whitened Cartesian Jacobian of `recording` at `truth`, over the free parameters that
// remain once `held` are held.
Eigen::MatrixXd DesignJacobian(const WorkcellProblem& problem, const Recording& recording,
                               const NoiseSpec& noise, const WorkcellEstimate& truth,
                               const HeldParameters& held) {
  WorkcellProblem cartesian = problem;
  cartesian.residual = ResidualForm::kCartesian;
  cartesian.noise = noise;
  const WorkcellData data = PrepareWorkcellData(cartesian, recording);
  auto assembled =
      AssembleWorkcell(cartesian, recording, data, BuildNoiseModel(recording, noise), truth);
  HoldParameters(&assembled->problem, held);
  Eigen::MatrixXd J;
  assembled->problem.Evaluate(nullptr, nullptr, &J, false);
  return J;
}

}  // namespace

bool PredictInCamera(const RobotModel& model, const WorkcellEstimate& e,
                     const PredictedTarget& what, const std::vector<double>& q,
                     Eigen::Vector3d* p_cam_mm) {
  Pose flange;
  if (!model.Forward(q.data(), e.model.at(what.robot).data(), &flange)) return false;
  const Pose T_world_flange = e.T_world_base.at(what.robot) * flange;
  *p_cam_mm = e.T_world_cam.at(what.camera).inverse() *
              (T_world_flange * e.T_flange_target.at(what.target).t);
  return true;
}

PredictionError ComparePredictions(const RobotModel& model, const WorkcellEstimate& estimate,
                                   const WorkcellEstimate& truth, const PredictedTarget& what,
                                   const std::vector<std::vector<double>>& commands) {
  PredictionError out;
  double sum = 0.0, sum2 = 0.0;
  for (const auto& q : commands) {
    Eigen::Vector3d a, b;
    if (!PredictInCamera(model, estimate, what, q, &a) ||
        !PredictInCamera(model, truth, what, q, &b)) {
      continue;
    }
    const double d = (a - b).norm();
    sum += d;
    sum2 += d * d;
    out.max_mm = std::max(out.max_mm, d);
    ++out.points;
  }
  if (out.points > 0) {
    out.mean_mm = sum / out.points;
    out.rms_mm = std::sqrt(sum2 / out.points);
  }
  return out;
}

double PredictionErrorFloorMm(const WorkcellProblem& problem, const Recording& design,
                              const PredictedTarget& what,
                              const std::vector<std::vector<double>>& validation,
                              const WorkcellEstimate& truth,
                              const std::vector<UnidentifiableParameter>& held) {
  const HeldParameters names = HeldOf(held);
  const Eigen::MatrixXd J = DesignJacobian(problem, design, problem.noise, truth, names);
  const int joints = validation.empty() ? 0 : static_cast<int>(validation.front().size());
  NoiseSpec unit;
  unit.position_sigma_mm[what.camera] = Eigen::Vector3d::Ones();
  const Eigen::MatrixXd G =
      DesignJacobian(problem, PredictionRecording(what, joints, validation), unit, truth, names);
  // F^-1 through the SVD of J (a pseudo-inverse where F is singular: those directions do not
  // change any prediction, or they would have been found unidentifiable).
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  Eigen::VectorXd inv_s = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] > 1e-12 * s[0]) inv_s[i] = 1.0 / s[i];
  }
  const Eigen::MatrixXd GV = G * svd.matrixV() * inv_s.asDiagonal();  // G F^-1 G^T = GV GV^T
  return std::sqrt(GV.squaredNorm() / std::max<size_t>(validation.size(), 1));
}

}  // namespace cellmetry
