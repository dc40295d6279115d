// A fitted cell's residual rows (residual_rows.h).
#include "residual_rows.h"

#include <limits>
#include <utility>

namespace cellmetry {

Eigen::VectorXd WhitenedResiduals(Problem& problem, const Linearization* at) {
  // The cost functions directly (EvaluateSparse without a Jacobian): the same residuals as
  // Ceres's Evaluate without the loss, without building a ceres::Problem for them (after a
  // Build, the first Evaluate made one: 22,500 residual blocks on exp_a, for one pass).
  Eigen::VectorXd r;
  if (at && at->valid && at->residuals.size() == problem.num_residuals()) {
    r = at->residuals;
  } else if (!problem.EvaluateSparse(&r, nullptr)) {
    r = Eigen::VectorXd::Constant(problem.num_residuals(),
                                  std::numeric_limits<double>::quiet_NaN());
  }
  return r;
}

std::vector<ResidualRow> ResidualRows(AssembledWorkcell& assembled, const Linearization* at) {
  Problem& problem = assembled.problem;
  const Eigen::VectorXd r = WhitenedResiduals(problem, at);
  std::vector<ResidualRow> rows;
  const auto& infos = problem.residual_infos();
  rows.reserve(infos.size());
  for (size_t b = 0; b < infos.size(); ++b) {
    const ResidualInfo& info = infos[b];
    if (info.kind == ResidualInfo::Kind::kPrior) continue;
    ResidualRow row;
    row.observation = info.observation;
    row.sample = info.sample;
    row.pose = info.pose;
    row.camera = info.camera;
    row.target = info.target;
    row.kind = info.kind;
    row.normalized = r.segment<3>(problem.residual_rows()[b]);
    row.error = row.normalized.cwiseProduct(info.sigma);
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace cellmetry
