// SolveCommand (compensation.h): Levenberg-Marquardt on the tool's pose error in the commands.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdio>

#include "cellmetry/basics/so3_jacobians.h"
#include "cellmetry/compensation/compensation.h"
#include "short_number.h"

namespace cellmetry {
namespace {

// The residual [p - p_target; w Log(R R_target^T)] at q and its Jacobian.
struct PoseResidual {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  double error_mm = NAN;
  double error_rad = NAN;
  double cost() const { return r.squaredNorm(); }
};

struct SolveRequest {
  const CompensationChain& chain;
  const Eigen::Vector3d& p;
  const Eigen::Matrix3d* R;  // null: position only
  const CommandContext& context;
  const CompensationOptions& options;
};

bool Evaluate(const SolveRequest& s, const std::vector<double>& q, PoseResidual* out) {
  Pose T;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;
  if (!ToolPoseJacobian(s.chain, q, s.context, &T, &J)) return false;
  const int n = static_cast<int>(q.size());
  const int rows = s.R ? 6 : 3;
  out->r.resize(rows);
  out->J.resize(rows, n);
  out->r.head<3>() = T.t - s.p;
  out->J.topRows(3) = J.topRows(3);
  out->error_mm = out->r.head<3>().norm();
  if (s.R) {
    const Eigen::Vector3d e = RotationError(T.R, *s.R);
    const double w = s.options.rotation_weight_mm_per_rad;
    out->r.tail<3>() = w * e;
    out->J.bottomRows(3) = w * InverseLeftJacobian(e) * J.bottomRows(3);
    out->error_rad = e.norm();
  }
  return true;
}

bool Converged(const SolveRequest& s, const PoseResidual& r, double share) {
  return r.error_mm <= share * s.options.tolerance_mm &&
         (!s.R || r.error_rad <= share * s.options.tolerance_rad);
}

// One damped Gauss-Newton step, no joint turned by more than max_step_rad.
Eigen::VectorXd Step(const PoseResidual& r, double lambda, double max_step_rad) {
  const Eigen::MatrixXd A = r.J.transpose() * r.J;
  Eigen::MatrixXd damped = A;
  damped.diagonal().array() += lambda;
  Eigen::VectorXd step = -damped.ldlt().solve(r.J.transpose() * r.r);
  const double largest = step.cwiseAbs().maxCoeff();
  if (largest > max_step_rad) step *= max_step_rad / largest;
  return step;
}

}  // namespace

SolvedCommand SolveCommand(const CompensationChain& chain, const Eigen::Vector3d& p_world_tool,
                           const Eigen::Matrix3d* R_world_tool, const std::vector<double>& seed,
                           const CommandContext& context, const CompensationOptions& options) {
  const SolveRequest request{chain, p_world_tool, R_world_tool, context, options};
  SolvedCommand out;
  out.q_rad = seed;
  PoseResidual current;
  if (!Evaluate(request, seed, &current)) {
    out.failure = "the robot has no pose at the seed: " +
                  chain.model->ForwardFailure(seed.data(), chain.params.data());
    return out;
  }
  // Damping relative to the Jacobian's scale; its floor keeps a redundant arm's steps (a
  // position target of a six-joint arm) out of the null space's far reaches.
  const double scale = std::max(1.0, (current.J.transpose() * current.J).diagonal().maxCoeff());
  double lambda = 1e-6 * scale;
  for (; out.iterations < options.max_iterations && !Converged(request, current, 1e-3);
       ++out.iterations) {
    std::vector<double> trial = out.q_rad;
    const Eigen::VectorXd step = Step(current, lambda, options.max_step_rad);
    for (size_t j = 0; j < trial.size(); ++j) trial[j] += step[j];
    PoseResidual next;
    if (Evaluate(request, trial, &next) && next.cost() < current.cost()) {
      out.q_rad = trial;
      current = next;
      lambda = std::max(lambda / 10.0, 1e-9 * scale);
    } else {
      lambda *= 10.0;
      if (lambda > 1e12 * scale) break;  // no step lowers the error: the closest this seed gets
    }
  }
  out.error_mm = current.error_mm;
  out.error_rad = current.error_rad;
  out.reached = Converged(request, current, 1.0);
  if (!out.reached) {
    out.failure = "out of reach: the calibrated robot comes no closer than " +
                  ShortNumber(current.error_mm) + " mm" +
                  (R_world_tool ? " and " + ShortNumber(current.error_rad) + " rad" : "") +
                  " (tolerance " + ShortNumber(options.tolerance_mm) + " mm" +
                  (R_world_tool ? ", " + ShortNumber(options.tolerance_rad) + " rad" : "") + ")";
  }
  return out;
}

}  // namespace cellmetry
