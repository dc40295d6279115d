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

// The columns `columns` of J (zero where -1), as J times a selection matrix: sparse stays sparse.
SparseJacobian Select(const SparseJacobian& J, const std::vector<int>& columns) {
  Eigen::SparseMatrix<double> selection(J.cols(), static_cast<Eigen::Index>(columns.size()));
  for (size_t k = 0; k < columns.size(); ++k) {
    if (columns[k] >= 0) selection.insert(columns[k], static_cast<Eigen::Index>(k)) = 1.0;
  }
  return J * selection;
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
  const SparseJacobian J_t = Select(at.jacobian, Columns(augmented, estimated));
  const SparseJacobian J_c = Select(at.jacobian, Columns(augmented, inputs));
  const Eigen::MatrixXd cross = Eigen::MatrixXd(J_t.transpose() * J_c);
  const Eigen::MatrixXd G = -bread * cross;
  if (sensitivity) *sensitivity = G;
  Eigen::MatrixXd cov = G * sigma.cwiseAbs2().asDiagonal() * G.transpose();
  return cov.size() == n * n ? cov : Eigen::MatrixXd::Zero(n, n);
}

}  // namespace cellmetry
