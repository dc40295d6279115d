// Problem: one assembled least-squares problem that every solver works on.
//
// A facade over four parts, each with its own contract:
//   BlockRegistry             (block_registry.h) named parameter blocks, whitened residual
//                             blocks, held entries, priors and robust losses, and the rows and
//                             columns Build() makes of them;
//   EvaluationLayout          (src/evaluation_layout.h) what the evaluators walk, laid out from
//                             the registry by Build() (kept where neither rows nor columns
//                             changed);
//   CeresAdapter              (src/ceres_adapter.h) the registry as ceres::Problems, one whose
//                             rows are the registry's and one to solve, and the dense Evaluate();
//   SparseEvaluator           (src/sparse_evaluator.h) residuals, the sparse Jacobian and its
//                             Gram rows, or a few of its columns, the cost functions called
//                             directly on every core;
//   NormalEquationsEvaluator  (src/normal_equations_evaluator.h) the robust cost's normal
//                             equations (normal_equations.h), summed without storing J.
//
// Ceres solves ceres_problem_for_solving() directly; other solvers read and write the free
// parameters as one vector (FreeValues / SetFreeValues) and call Evaluate() for residuals and
// the dense Jacobian with respect to that vector, or EvaluateNormalEquations().
//
// Build() must be called after adding blocks and residuals, and again after SetFixed(),
// SetPrior() or a robust loss; it is cheap (no cost function is made again).
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cellmetry/basics/parameter.h"
#include "cellmetry/estimation/block_registry.h"
#include "cellmetry/estimation/gram_rows.h"
#include "cellmetry/estimation/normal_equations.h"
#include "cellmetry/estimation/r_factor.h"

namespace cellmetry {

class CeresAdapter;
struct EvaluationLayout;

class Problem {
 public:
  Problem();
  ~Problem();
  Problem(const Problem&) = delete;
  Problem& operator=(const Problem&) = delete;

  // Blocks, residuals and what Build() lays out: the registry's (block_registry.h says each).
  int AddBlock(const std::string& name, std::vector<Parameter> params) {
    return registry_.AddBlock(name, std::move(params));
  }
  int FindBlock(const std::string& name) const { return registry_.FindBlock(name); }
  int num_blocks() const { return registry_.num_blocks(); }
  const std::string& block_name(int block) const { return registry_.block_name(block); }
  const std::vector<Parameter>& block_parameters(int block) const {
    return registry_.block_parameters(block);
  }
  double* values(int block) { return registry_.values(block); }
  const double* values(int block) const { return registry_.values(block); }
  void SetFixed(int block, int index, bool fixed) { registry_.SetFixed(block, index, fixed); }
  void SetPrior(int block, int index, double mean, double sigma) {
    registry_.SetPrior(block, index, mean, sigma);
  }
  void ReserveResiduals(int num_blocks) { registry_.ReserveResiduals(num_blocks); }
  void AddResidual(std::unique_ptr<ceres::CostFunction> cost, const std::vector<int>& blocks,
                   const ResidualInfo& info) {
    registry_.AddResidual(std::move(cost), blocks, info);
  }
  void SetRobustLoss(RobustLossKind kind, double scale) { registry_.SetRobustLoss(kind, scale); }
  void SetWhitenedRobustLoss(RobustLossKind kind, std::vector<double> whitened_scale) {
    registry_.SetWhitenedRobustLoss(kind, std::move(whitened_scale));
  }
  void Build();

  const std::vector<FreeParameter>& free_parameters() const { return registry_.free_parameters(); }
  int num_free() const { return registry_.num_free(); }
  int num_residuals() const { return registry_.num_residuals(); }
  int num_residual_blocks() const { return registry_.num_residual_blocks(); }
  const std::vector<ResidualInfo>& residual_infos() const { return registry_.residual_infos(); }
  // First row of each residual block in every evaluation's output.
  const std::vector<int>& residual_rows() const { return registry_.residual_rows(); }
  // Predictions the normal equations and the sparse Jacobian evaluate after Build(): one per
  // unit of blocks sharing one (shared_prediction_cost.h), one per other block.
  int num_predictions() const;
  Eigen::VectorXd FreeValues() const { return registry_.FreeValues(); }
  void SetFreeValues(const Eigen::VectorXd& x) { registry_.SetFreeValues(x); }
  Eigen::VectorXd LowerBounds() const { return registry_.LowerBounds(); }
  Eigen::VectorXd UpperBounds() const { return registry_.UpperBounds(); }

  // The ceres::Problem whose rows are Evaluate()'s (in another order), built on first use: a
  // problem only linearized never pays for Ceres's own structures.
  ceres::Problem& ceres_problem();
  // A ceres::Problem to solve: the same minimum, steps and reported costs as ceres_problem(),
  // over fewer rows (the positions of a unit sharing a prediction summed into 3 rows). Its
  // residuals are not Evaluate()'s rows. Built on first use, again after Build().
  ceres::Problem& ceres_problem_for_solving();
  // Residuals (whitened) and, when `jacobian` is not null, the dense Jacobian with respect to
  // FreeValues(), at the current values, by Ceres. Returns false if a cost function failed.
  bool Evaluate(double* cost, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian,
                bool apply_loss = true);

  // The same without the robust loss and with the Jacobian sparse: what a large cell needs (a
  // dense Jacobian of 240,000 rows x 200 columns is 380 MB; its nonzeros a tenth of that).
  // With `gram` also the rows with J's Gram matrix (gram_rows.h), where they are at most a
  // quarter of J's (else `gram` is left empty and J serves: GramOf). Without `jacobian`, the
  // Gram rows alone, J never stored: only where HasGramRows() (what needs J^T J alone, as the
  // identifiability check before a solve, is spared exp_a's million entries).
  bool EvaluateSparse(Eigen::VectorXd* residuals, SparseJacobian* jacobian,
                      GramRows* gram = nullptr) const;
  bool HasGramRows() const;
  // The Jacobian's columns of the free entries of `blocks` alone (ids from AddBlock), in
  // FreeValues() order and numbered from 0 (`columns`: each one's index into
  // free_parameters()). Only the residual blocks that read one of `blocks` are evaluated, and
  // each differentiates only those: a few columns of a large problem cost a few columns, not
  // all of them. Every residual has its row; rows of the blocks not evaluated are empty.
  bool EvaluateSparseColumns(const std::vector<int>& blocks, SparseJacobian* jacobian,
                             std::vector<int>* columns) const;
  // The normal equations (normal_equations.h) at the current values, summed block by block on
  // every core without storing J, in a fixed order (the same bits on every run). False if a
  // cost function failed.
  bool EvaluateNormalEquations(NormalEquations* out) const;

 private:
  BlockRegistry registry_;
  std::unique_ptr<EvaluationLayout> layout_;  // of registry_, as the last Build() laid it out
  std::unique_ptr<CeresAdapter> ceres_;       // after both: its views point into them
};

// The whitened residuals and their sparse Jacobian with respect to FreeValues() at the current
// values, without the robust loss: what the covariance and its robust forms are computed from.
// Evaluate once at the answer and hand it to each (ComputeUncertainty, ClusterRobustCovariance).
struct Linearization {
  Linearization() = default;
  Linearization(const Linearization&) = default;
  Linearization& operator=(const Linearization&) = default;
  // Eigen 3.4's SparseMatrix has no move: its "move" copies every entry (exp_a's Jacobian is a
  // million). These swap, so handing a solve's linearization on to the covariance copies none.
  Linearization(Linearization&& other) noexcept { *this = std::move(other); }
  Linearization& operator=(Linearization&& other) noexcept {
    residuals = std::move(other.residuals);
    jacobian.swap(other.jacobian);
    valid = other.valid;
    gram.rows.swap(other.gram.rows);
    gram.block = std::move(other.gram.block);
    gram.row_of_block = std::move(other.gram.row_of_block);
    r_factor = std::move(other.r_factor);
    return *this;
  }

  Eigen::VectorXd residuals;
  SparseJacobian jacobian;
  bool valid = false;  // false: a cost function failed at these values (no numbers to trust)
  // Rows with J's Gram matrix (gram_rows.h), what its R factors are computed from; filled with
  // the Jacobian by Linearize and FindUnidentifiable.
  GramRows gram;
  // RFactor(jacobian) (r_factor.h) once something computed it (FindUnidentifiable); empty
  // before. Whoever needs it next takes it from here instead of factoring J again.
  Eigen::MatrixXd r_factor;
};
Linearization Linearize(Problem& problem);
// The rows R factors and column norms are computed from: the Gram rows where they were made,
// else J itself.
const SparseJacobian& GramOf(const Linearization& at);

}  // namespace cellmetry
