// The covariance inherited from uncertain held inputs (consider_covariance.h).
#include "cellmetry/estimation/consider_covariance.h"

#include <map>
#include <stdexcept>

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

}  // namespace

Eigen::MatrixXd ConsiderCrossProduct(const Problem& augmented, const NormalEquations& at,
                                     const std::vector<std::string>& estimated,
                                     const std::vector<std::string>& inputs) {
  const std::vector<int> rows = Columns(augmented, estimated);
  const std::vector<int> columns = Columns(augmented, inputs);
  Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()),
                                                static_cast<Eigen::Index>(columns.size()));
  for (size_t t = 0; t < rows.size(); ++t) {
    for (size_t c = 0; c < columns.size(); ++c) {
      if (rows[t] >= 0 && columns[c] >= 0) cross(t, c) = at.hessian(rows[t], columns[c]);
    }
  }
  return cross;
}

Eigen::MatrixXd ConsiderCovariance(const Eigen::MatrixXd& cross, const Eigen::MatrixXd& bread,
                                   const Eigen::VectorXd& input_sigma,
                                   Eigen::MatrixXd* sensitivity) {
  const Eigen::Index n = bread.rows();
  if (n == 0 || input_sigma.size() == 0) return Eigen::MatrixXd::Zero(n, n);
  if (cross.rows() != n || cross.cols() != input_sigma.size()) {
    throw std::invalid_argument("ConsiderCovariance: cross is not estimated x inputs");
  }
  const Eigen::MatrixXd G = -bread * cross;
  if (sensitivity) *sensitivity = G;
  return G * input_sigma.cwiseAbs2().asDiagonal() * G.transpose();
}

}  // namespace cellmetry
