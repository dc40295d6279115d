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
  rows.reserve(assembled.labels.size());
  for (size_t b = 0; b < assembled.labels.size(); ++b) {  // the priors after them measure nothing
    const ResidualInfo& info = infos[b];
    const MeasurementLabel& label = assembled.labels[b];
    ResidualRow row;
    row.observation = label.observation;
    row.sample = label.sample;
    row.pose = label.pose;
    row.camera = label.camera;
    row.target = label.target;
    row.kind = info.kind;
    row.normalized = r.segment<3>(problem.residual_rows()[b]);
    row.error = row.normalized.cwiseProduct(info.sigma);
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace cellmetry
