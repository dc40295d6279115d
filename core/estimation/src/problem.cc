// Problem (problem.h): the registry and its evaluators composed, and Linearize.
#include "cellmetry/estimation/problem.h"

#include <memory>
#include <string>
#include <vector>

#include "ceres_adapter.h"
#include "evaluation_layout.h"
#include "normal_equations_evaluator.h"
#include "sparse_evaluator.h"

namespace cellmetry {

int FindParameter(const std::vector<Parameter>& params, const std::string& name) {
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

Problem::Problem()
    : layout_(std::make_unique<EvaluationLayout>()),
      ceres_(std::make_unique<CeresAdapter>(&registry_, layout_.get())) {}
Problem::~Problem() = default;

void Problem::Build() {
  // The Ceres views point at the losses and priors the registry makes again: dropped first,
  // made again when a solver or Evaluate() next needs them.
  ceres_->Reset();
  registry_.Build();
  layout_->Update(registry_);
}

int Problem::num_predictions() const { return layout_->num_units(); }

ceres::Problem& Problem::ceres_problem() { return ceres_->for_evaluation(); }

ceres::Problem& Problem::ceres_problem_for_solving() { return ceres_->for_solving(); }

bool Problem::Evaluate(double* cost, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian,
                       bool apply_loss) {
  return ceres_->Evaluate(cost, residuals, jacobian, apply_loss);
}

bool Problem::EvaluateSparse(Eigen::VectorXd* residuals, SparseJacobian* jacobian,
                             GramRows* gram) const {
  return SparseEvaluator(registry_, *layout_).Evaluate(residuals, jacobian, gram);
}

bool Problem::HasGramRows() const { return SparseEvaluator(registry_, *layout_).HasGramRows(); }

bool Problem::EvaluateSparseColumns(const std::vector<int>& blocks, SparseJacobian* jacobian,
                                    std::vector<int>* columns) const {
  return SparseEvaluator(registry_, *layout_).EvaluateColumns(blocks, jacobian, columns);
}

bool Problem::EvaluateNormalEquations(NormalEquations* out) const {
  return NormalEquationsEvaluator(registry_, *layout_).Evaluate(out);
}

Linearization Linearize(Problem& problem) {
  Linearization at;
  at.valid = problem.EvaluateSparse(&at.residuals, &at.jacobian, &at.gram);
  return at;
}

const SparseJacobian& GramOf(const Linearization& at) {
  return at.gram.rows.rows() > 0 || at.jacobian.rows() == 0 ? at.gram.rows : at.jacobian;
}

}  // namespace cellmetry
