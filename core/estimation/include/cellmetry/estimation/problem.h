// Problem: one assembled least-squares problem that every solver works on.
//
// It holds named parameter blocks (a frame, a robot's geometry table), the residual blocks that
// tie them to measurements, and a ceres::Problem built from both. Residuals are whitened: each
// row is (prediction - measurement) / sigma, so 0.5 * |r|^2 is the negative log-likelihood and
// (J^T J)^-1 is the covariance of the free parameters.
//
// Ceres solves the ceres::Problem directly; other solvers read and write the free parameters as
// one vector (FreeValues / SetFreeValues) and call Evaluate() for residuals and the dense
// Jacobian with respect to that vector. Fixed entries of a block are held by a SubsetManifold,
// fully fixed blocks are constant, and blocks no residual uses are left out.
//
// Build() must be called after adding blocks and residuals, and again after SetFixed(),
// SetPrior() or SetRobustLoss(); it is cheap (no cost function is recreated).
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cellmetry/basics/parameter.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/estimation/gram_rows.h"
#include "cellmetry/estimation/normal_equations.h"
#include "cellmetry/estimation/r_factor.h"

namespace cellmetry {

// How one residual block is weighed, for statistics: its kind, and the sigma each row was
// divided by (mm for positions, rad for rotations, the entry's unit for priors). What a block
// measured is the caller's to keep.
struct ResidualInfo {
  enum class Kind { kPosition, kRotation, kPrior };
  Kind kind = Kind::kPosition;
  Eigen::Vector3d sigma = Eigen::Vector3d::Ones();
};

enum class RobustLossKind { kNone, kHuber, kCauchy };

struct FreeParameter {
  int block = 0;
  int index = 0;
  std::string name;  // "<block>.<parameter>", e.g. "ur3.base.x"
  std::string unit;
};

class Problem {
 public:
  Problem();
  ~Problem();
  Problem(const Problem&) = delete;
  Problem& operator=(const Problem&) = delete;

  // Adds a block named `name` whose values start at each parameter's nominal. Returns its id.
  int AddBlock(const std::string& name, std::vector<Parameter> params);
  int FindBlock(const std::string& name) const;  // -1 if absent
  int num_blocks() const { return static_cast<int>(blocks_.size()); }
  const std::string& block_name(int block) const;
  const std::vector<Parameter>& block_parameters(int block) const;
  double* values(int block);
  const double* values(int block) const;
  void SetFixed(int block, int index, bool fixed);
  // A Gaussian prior on one entry: (value - mean) / sigma, a row of kind kPrior from the next
  // Build() on. The entry's nominal becomes `mean` (after AddBlock a nominal is read only as the
  // prior's mean).
  void SetPrior(int block, int index, double mean, double sigma);

  // Room for `num_blocks` residual blocks in all, so adding them does not grow and copy the
  // lists (an assembly knows its count: tens of thousands on a real recording).
  void ReserveResiduals(int num_blocks);
  // Adds a residual block over `blocks` (ids from AddBlock). The Problem owns `cost`.
  void AddResidual(std::unique_ptr<ceres::CostFunction> cost, std::vector<int> blocks,
                   ResidualInfo info);

  // A robust loss on every measurement block; `scale` is in the measurement's unit (mm or rad)
  // and is divided by the block's RMS sigma to act on whitened residuals.
  void SetRobustLoss(RobustLossKind kind, double scale);
  // A robust loss per measurement block, in whitened units: block i's loss bends where its
  // whitened norm |r_i| reaches `whitened_scale[i]` (<= 0 or not finite: no loss on that
  // block). What a fit that must not be pulled by gross errors needs when blocks of one kind
  // scatter differently (outliers.h). Replaced by, and replaces, SetRobustLoss's.
  void SetWhitenedRobustLoss(RobustLossKind kind, std::vector<double> whitened_scale);

  void Build();
  // The ceres::Problem of what Build() set up, built on first use: a problem only linearized
  // (EvaluateSparse: the covariance, the uncertain inputs) never pays for Ceres's own structures.
  // Its rows are Evaluate()'s (in another order).
  ceres::Problem& ceres_problem();
  // A ceres::Problem to solve: the same minimum, steps and reported costs as ceres_problem(),
  // over fewer rows. The blocks of a unit that compare one predicted position with measured
  // ones (the captures of a pose, a static camera's views of the world tag) are summed into 3
  // rows exactly, their cost's constant part a block without parameters
  // (summed_position_group.h). Its residuals are not Evaluate()'s rows: read rows from
  // Evaluate(). Built on first use, again after Build().
  ceres::Problem& ceres_problem_for_solving();

  const std::vector<FreeParameter>& free_parameters() const { return free_; }
  int num_free() const { return static_cast<int>(free_.size()); }
  int num_residuals() const { return num_residuals_; }
  const std::vector<ResidualInfo>& residual_infos() const { return infos_; }
  // First row of each residual block in Evaluate()'s output.
  const std::vector<int>& residual_rows() const { return rows_; }
  // Predictions the normal equations and the sparse Jacobian evaluate after Build(): one per
  // unit of blocks sharing one (shared_prediction_cost.h), one per other block.
  int num_predictions() const { return static_cast<int>(unit_start_.size()) - 1; }

  Eigen::VectorXd FreeValues() const;
  void SetFreeValues(const Eigen::VectorXd& x);
  Eigen::VectorXd LowerBounds() const;  // -inf where unbounded
  Eigen::VectorXd UpperBounds() const;  // +inf where unbounded

  // Residuals (whitened) and, when `jacobian` is not null, the dense Jacobian with respect to
  // FreeValues(), at the current values. Returns false if a cost function failed.
  bool Evaluate(double* cost, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian,
                bool apply_loss = true);
  // The same without the robust loss and with the Jacobian sparse: what a large cell needs (a
  // dense Jacobian of 240,000 rows x 200 columns is 380 MB; its nonzeros a tenth of that). The
  // cost functions are called directly, on every core (Ceres's Evaluate builds a program of
  // the chosen blocks at every call, which costs more than the evaluation).
  // With `gram` also the rows with J's Gram matrix (gram_rows.h), where they are at most a
  // quarter of J's (else `gram` is left empty and J serves: GramOf). Without `jacobian`, the
  // Gram rows alone, J never stored: only where HasGramRows() (what needs J^T J alone, as the
  // identifiability check before a solve, is spared exp_a's million entries).
  bool EvaluateSparse(Eigen::VectorXd* residuals, SparseJacobian* jacobian,
                      GramRows* gram = nullptr) const;
  // Whether EvaluateSparse makes Gram rows: they are at most a quarter of J's rows.
  bool HasGramRows() const;
  // The Jacobian's columns of the free entries of `blocks` alone (ids from AddBlock), in
  // FreeValues() order and numbered from 0 (`columns`: each one's index into
  // free_parameters()). Only the residual blocks that read one of `blocks` are evaluated, and
  // each differentiates only those (an automatic-differentiation cost seeds only the
  // parameters asked for): a few columns of a large problem cost a few columns, not all of
  // them. Every residual has its row; rows of the blocks not evaluated are empty.
  bool EvaluateSparseColumns(const std::vector<int>& blocks, SparseJacobian* jacobian,
                             std::vector<int>* columns) const;
  // The normal equations (normal_equations.h), accumulated block by block on every core without storing J
  // (normal_equations.cc): for a cell's few dozen free parameters and tens of thousands of
  // blocks, what an iteration of a reweighted fit needs at a fraction of a sparse J's cost.
  // The sum's order is fixed (the same bits on every run). False if a cost function failed.
  bool EvaluateNormalEquations(NormalEquations* out) const;

 private:
  struct Block;
  struct Residual;
  struct BlockEvaluation;  // problem_blocks.h
  struct NormalEquationsRange;  // normal_equations.cc: one range of units summed
  // Evaluates residual block k (evaluation order) into `scratch`, differentiating the slots
  // scratch->asked marks (none when `with_jacobians` is false). False if the cost failed.
  bool EvaluateBlock(int k, bool with_jacobians, BlockEvaluation* scratch) const;
  // Marks in scratch->asked the slots of residual block k that hold a free entry.
  void AskFreeSlots(int k, BlockEvaluation* scratch) const;
  // Points scratch's parameters at residual block k's blocks and, with `with_jacobians`, gives
  // each asked slot room for `num_rows` rows of its Jacobian (EvaluateBlock, PredictBlock).
  void PrepareSlots(int k, int num_rows, bool with_jacobians, BlockEvaluation* scratch) const;
  // The first `num_rows` rows of residual block k's Jacobian in `scratch`, at its free columns
  // (in column order), into `rows`, row-major; returns the number of columns.
  int GatherFreeColumns(int k, int num_rows, const BlockEvaluation& scratch,
                        std::vector<double>* rows) const;
  // The shared prediction of residual block k (a SharedPredictionCost) into `prediction`, its
  // tangent Jacobians (3 rows) into scratch->jacobians for the slots scratch->asked marks.
  bool PredictBlock(int k, BlockEvaluation* scratch, Pose* prediction) const;
  // EvaluateSparse's work for one residual block, and for a unit sharing a prediction: its
  // residuals into `r`, its rows of J's compressed row storage when `column_index` is not
  // null, and its Gram rows when `gram` is not.
  struct SparseOutput {
    double* r;
    int* column_index;  // null: no Jacobian
    double* entries;
    GramRows* gram = nullptr;  // with its first row per unit, then the end
    const int* gram_unit_row = nullptr;
  };
  // Sizes `gram` for EvaluateSparse and returns each unit's first row (then the end); empty,
  // and `gram` left empty, where they would be more than a quarter of J's rows.
  std::vector<int> LayOutGramRows(GramRows* gram) const;
  // The number of Gram rows (3 per unit sharing a prediction, a block's own rows otherwise)
  // and, with `unit_row`, each unit's first (then the end).
  int NumGramRows(std::vector<int>* unit_row) const;
  // Residual block k's Jacobian rows from `scratch` into compressed rows at its free columns:
  // row i's entries from row_start[i].
  void WriteBlockRows(int k, const BlockEvaluation& scratch, const int* row_start,
                      int* column_index, double* entries) const;
  // The 3 Gram rows L^T A of unit u (L L^T = `information`, A = `tangent`, 3 x width
  // row-major at the unit's free columns).
  void AddGramRows(int u, const Eigen::Matrix3d& information, const double* tangent, int width,
                   const SparseOutput& out) const;
  // (EvaluateBlockRows: unit u's one block, whose Gram rows are its own rows.)
  bool EvaluateBlockRows(int u, BlockEvaluation* scratch, const SparseOutput& out) const;
  bool EvaluateSharedRows(int u, BlockEvaluation* scratch, const SparseOutput& out) const;

  std::vector<std::unique_ptr<Block>> blocks_;
  std::vector<Residual> residuals_;
  std::vector<ResidualInfo> infos_;
  std::vector<std::unique_ptr<ceres::CostFunction>> prior_costs_;
  std::vector<std::unique_ptr<ceres::LossFunction>> losses_;
  // A ceres::Problem over this Problem's blocks (problem_ceres.cc), one to evaluate rows and
  // one to solve (ceres_problem(), ceres_problem_for_solving()).
  struct CeresView {
    std::vector<ceres::ResidualBlockId> residual_ids;
    // The Ceres blocks made for units (shared_prediction_group.h, summed_position_group.h) and
    // the constant's block, which this view owns; the others are the Problem's.
    std::vector<std::unique_ptr<ceres::CostFunction>> unit_costs;
    std::vector<std::unique_ptr<ceres::Manifold>> manifolds;
    std::vector<double*> variable_blocks;
    // The row in Evaluate()'s order of each of Ceres's rows (empty: the same order); only for
    // the view to evaluate.
    std::vector<int> rows;
    std::vector<double*> scratch_pointers;  // AddCeresResidual's, kept to spare an allocation
    std::unique_ptr<ceres::Problem> problem;  // last: destroyed first, before what it points to
    void Reset();
  };
  CeresView for_evaluation_, for_solving_;
  std::vector<FreeParameter> free_;
  std::vector<int> rows_;
  // Per residual block (in rows_ order): its cost and parameter blocks (one of block_lists_:
  // Build makes them again after any change); per block and entry, its column among the free
  // parameters (-1: fixed).
  std::vector<std::pair<ceres::CostFunction*, const std::vector<int>*>> evaluation_order_;
  // Each distinct list of parameter blocks a residual reads, once, at a stable address: a
  // recording's tens of thousands of blocks read a few dozen lists, so two blocks read the same
  // blocks exactly when they point at the same list (the layout compares pointers, not lists).
  std::deque<std::vector<int>> block_lists_;
  std::map<std::vector<int>, const std::vector<int>*> list_of_blocks_;
  std::vector<const std::vector<int>*> recent_lists_;  // InternBlocks's last few, checked first
  const std::vector<int>* InternBlocks(const std::vector<int>& blocks);
  std::vector<ceres::LossFunction*> evaluation_losses_;  // per residual block; null: none
  // `summed`: the view to solve (positions summed); else the view to evaluate.
  void BuildCeres(bool summed, CeresView* view);
  // BuildCeres's residual blocks, units grouped (or summed) where they can be.
  void AddCeresResiduals(bool summed, CeresView* view);
  // `cost` over residual block k's parameter blocks into `view`.
  void AddCeresResidual(ceres::CostFunction* cost, ceres::LossFunction* loss, int k,
                        CeresView* view);
  std::vector<std::vector<int>> free_column_;
  // Build()'s steps: forget what the last Build made; each measurement's row with its robust
  // loss; the free parameters' columns and their priors' rows. AppendRow puts one residual
  // block in evaluation order.
  void ClearBuilt();
  void AddMeasurementRows();
  void AddFreeColumnsAndPriors();
  void AppendRow(ceres::CostFunction* cost, ceres::LossFunction* loss,
                 const std::vector<int>& block_ids);
  // EvaluateSparse's layout, fixed by Build(): per residual block the free columns its rows
  // hold, in column order, with the slot and entry of the parameter block each comes from.
  struct SparseEntry {
    int column, slot, index;
  };
  void BuildSparseLayout();
  // Each pattern (list of parameter blocks) once; per residual block, its pattern's range.
  std::vector<SparseEntry> sparse_entries_;
  struct EntryRange {
    int begin = 0, end = 0;
  };
  std::vector<EntryRange> block_entries_;  // per residual block, into sparse_entries_
  // Residual blocks whose free columns are the same list (every observation of one tool by one
  // camera, say) share a column group: the normal equations sum each group densely.
  std::vector<int> column_group_;                 // per residual block
  std::vector<std::vector<int>> group_columns_;   // per group, ascending
  std::vector<int> sparse_row_start_;    // per row, then the end: the CRS row pointers
  // What the layout above was made from: residual blocks and free columns (Build skips it
  // when neither changed).
  int layout_num_blocks_ = -1;
  std::vector<std::vector<int>> layout_free_column_;
  // Residual blocks in units that share one prediction (shared_prediction_cost.h: the same key
  // over the same parameter blocks), each unit's blocks ascending, units in the order of their
  // first block; a block that shares nothing is a unit alone. Made with the layout.
  void BuildPredictionUnits();
  std::vector<int> unit_blocks_;
  std::vector<int> unit_start_;  // per unit, into unit_blocks_; then the end
  // A unit of more than one block is evaluated once for its blocks; one block alone as any.
  bool SharesPrediction(int u) const { return unit_start_[u + 1] - unit_start_[u] > 1; }
  // Consecutive units in chunks of about the same number of blocks, what the evaluations split
  // among the cores (a range of units would put a static camera's world-tag units, thousands of
  // blocks, all at the end in one range): per chunk, its first unit; then the end.
  std::vector<int> chunk_start_;
  int num_residuals_ = 0;
  RobustLossKind loss_kind_ = RobustLossKind::kNone;
  double loss_scale_ = 1.0;
  std::vector<double> loss_whitened_scale_;  // per measurement block; empty: loss_scale_
  int num_measurement_residuals_ = 0;
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
  bool valid = false;   // false: a cost function failed at these values (no numbers to trust)
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
