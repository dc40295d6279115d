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

// J[:, estimated]^T J[:, inputs] read off J^T J (zero rows and columns where a column is -1).
Eigen::MatrixXd CrossProduct(const Eigen::MatrixXd& hessian, const std::vector<int>& estimated,
                             const std::vector<int>& inputs) {
  Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(estimated.size()),
                                                static_cast<Eigen::Index>(inputs.size()));
  for (size_t t = 0; t < estimated.size(); ++t) {
    for (size_t c = 0; c < inputs.size(); ++c) {
      if (estimated[t] >= 0 && inputs[c] >= 0) cross(t, c) = hessian(estimated[t], inputs[c]);
    }
  }
  return cross;
}

}  // namespace

Eigen::MatrixXd ConsiderCovariance(const Problem& augmented, const NormalEquations* at,
                                   const std::vector<std::string>& estimated,
                                   const Eigen::MatrixXd& bread,
                                   const std::map<std::string, double>& input_sigma,
                                   Eigen::MatrixXd* sensitivity) {
  const Eigen::Index n = static_cast<Eigen::Index>(estimated.size());
  if (at == nullptr) {
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
      CrossProduct(at->hessian, Columns(augmented, estimated), Columns(augmented, inputs));
  const Eigen::MatrixXd G = -bread * cross;
  if (sensitivity) *sensitivity = G;
  Eigen::MatrixXd cov = G * sigma.cwiseAbs2().asDiagonal() * G.transpose();
  return cov.size() == n * n ? cov : Eigen::MatrixXd::Zero(n, n);
}

}  // namespace cellmetry
