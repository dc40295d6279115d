// The covariance inherited from uncertain held inputs (consider_covariance.h).
#include "cellmetry/estimation/consider_covariance.h"

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

// Column of each name among `problem`'s free parameters; -1 where it is not free there.
std::vector<int> Columns(const Problem& problem, const std::vector<std::string>& names) {
  std::map<std::string, int> column;
  const auto& free = problem.free_parameters();
  for (size_t i = 0; i < free.size(); ++i) column[free[i].name] = static_cast<int>(i);
  std::vector<int> out;
  for (const auto& name : names) {
    const auto it = column.find(name);
    out.push_back(it == column.end() ? -1 : it->second);
  }
  return out;
}

// J[:, estimated]^T J[:, inputs] (zero rows and columns where a column is -1), accumulated row
// by row over J's nonzeros: a row touches a few of both, and no selected copy of J is formed.
Eigen::MatrixXd CrossProduct(const SparseJacobian& J, const std::vector<int>& estimated,
                             const std::vector<int>& inputs) {
  std::vector<int> as_estimated(J.cols(), -1), as_input(J.cols(), -1);
  for (size_t k = 0; k < estimated.size(); ++k) {
    if (estimated[k] >= 0) as_estimated[estimated[k]] = static_cast<int>(k);
  }
  for (size_t k = 0; k < inputs.size(); ++k) {
    if (inputs[k] >= 0) as_input[inputs[k]] = static_cast<int>(k);
  }
  Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(estimated.size()),
                                                static_cast<Eigen::Index>(inputs.size()));
  std::vector<std::pair<int, double>> row_estimated, row_inputs;
  for (Eigen::Index row = 0; row < J.outerSize(); ++row) {
    row_estimated.clear();
    row_inputs.clear();
    for (SparseJacobian::InnerIterator it(J, row); it; ++it) {
      const int t = as_estimated[it.col()], c = as_input[it.col()];
      if (t >= 0) row_estimated.emplace_back(t, it.value());
      if (c >= 0) row_inputs.emplace_back(c, it.value());
    }
    for (const auto& [c, v] : row_inputs) {
      for (const auto& [t, u] : row_estimated) cross(t, c) += u * v;
    }
  }
  return cross;
}

}  // namespace

Eigen::MatrixXd ConsiderCovariance(const Problem& augmented, const Linearization& at,
                                   const std::vector<std::string>& estimated,
                                   const Eigen::MatrixXd& bread,
                                   const std::map<std::string, double>& input_sigma,
                                   Eigen::MatrixXd* sensitivity) {
  const Eigen::Index n = static_cast<Eigen::Index>(estimated.size());
  if (!at.valid) {
    throw InputError({}, "the model cannot be evaluated at the answer with its uncertain inputs",
                     "Check the uncertain_inputs: section of the job");
  }
  std::vector<std::string> inputs;
  Eigen::VectorXd sigma(input_sigma.size());
  for (const auto& [name, s] : input_sigma) {
    sigma[static_cast<Eigen::Index>(inputs.size())] = s;
    inputs.push_back(name);
  }
  const Eigen::MatrixXd cross =
      CrossProduct(at.jacobian, Columns(augmented, estimated), Columns(augmented, inputs));
  const Eigen::MatrixXd G = -bread * cross;
  if (sensitivity) *sensitivity = G;
  Eigen::MatrixXd cov = G * sigma.cwiseAbs2().asDiagonal() * G.transpose();
  return cov.size() == n * n ? cov : Eigen::MatrixXd::Zero(n, n);
}

}  // namespace cellmetry
