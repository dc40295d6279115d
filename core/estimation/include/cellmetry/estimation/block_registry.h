// BlockRegistry: the parameter blocks and residual blocks of one least-squares problem, which
// entries are held, which have a prior, which blocks have a robust loss, and the rows and columns
// Build() lays them out in. It evaluates nothing: the evaluators read it (Problem, problem.h,
// composes them).
//
// Parameter blocks are named lists of Parameters; each block's values live at one address for
// the registry's life (values(block)), where the cost functions and Ceres read them in place.
//
// Residual blocks are whitened: each row is (prediction - measurement) / sigma, so 0.5 * |r|^2 is
// the negative log-likelihood and (J^T J)^-1 the covariance of the free parameters. The caller
// owns what a block is about; the registry keeps only how it is weighed (ResidualInfo).
//
// Build() lays out, and must be called after adding blocks and residuals and again after
// SetFixed(), SetPrior() or a robust loss; it is cheap (no cost function is made again):
//   rows     the residual blocks in evaluation order: the measurement blocks as added, then one
//            prior row per free entry with a prior, in block and entry order. Block k's rows
//            are residual_rows()[k] on; k indexes cost(), loss(), blocks_of() and
//            residual_infos() alike.
//   columns  the free parameters: the entries neither held nor in a block no residual reads,
//            in block and entry order. FreeValues()'s vector and every Jacobian's columns.
// What the evaluators walk is laid out from these (evaluation_layout.h, internal; Problem keeps
// it beside the registry).
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cellmetry/basics/parameter.h"

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

class BlockRegistry {
 public:
  BlockRegistry();
  ~BlockRegistry();
  BlockRegistry(const BlockRegistry&) = delete;
  BlockRegistry& operator=(const BlockRegistry&) = delete;

  // --- Parameter blocks ---
  // Adds a block named `name` whose values start at each parameter's nominal. Returns its id.
  int AddBlock(const std::string& name, std::vector<Parameter> params);
  int FindBlock(const std::string& name) const;  // -1 if absent
  int num_blocks() const { return static_cast<int>(blocks_.size()); }
  const std::string& block_name(int block) const { return blocks_[block]->name; }
  const std::vector<Parameter>& block_parameters(int block) const { return blocks_[block]->params; }
  int block_size(int block) const { return static_cast<int>(blocks_[block]->params.size()); }
  double* values(int block) { return blocks_[block]->values.data(); }
  const double* values(int block) const { return blocks_[block]->values.data(); }
  // Whether a residual block reads `block` (one that none reads has no free entries).
  bool used(int block) const { return blocks_[block]->used; }
  void SetFixed(int block, int index, bool fixed);
  // A Gaussian prior on one entry: (value - mean) / sigma, a row of kind kPrior from the next
  // Build() on. The entry's nominal becomes `mean` (after AddBlock a nominal is read only as the
  // prior's mean).
  void SetPrior(int block, int index, double mean, double sigma);

  // --- Residual blocks ---
  // Room for `num_blocks` residual blocks in all, so adding them does not grow and copy the
  // lists (an assembly knows its count: tens of thousands on a real recording).
  void ReserveResiduals(int num_blocks);
  // Adds a residual block over `blocks` (ids from AddBlock); the registry owns `cost`.
  void AddResidual(std::unique_ptr<ceres::CostFunction> cost, const std::vector<int>& blocks,
                   const ResidualInfo& info);

  // --- Robust losses (from the next Build() on) ---
  // A robust loss on every measurement block; `scale` is in the measurement's unit (mm or rad)
  // and is divided by the block's RMS sigma to act on whitened residuals.
  void SetRobustLoss(RobustLossKind kind, double scale);
  // A robust loss per measurement block, in whitened units: block i's loss bends where its
  // whitened norm |r_i| reaches `whitened_scale[i]` (<= 0 or not finite: no loss on that
  // block). What a fit that must not be pulled by gross errors needs when blocks of one kind
  // scatter differently. Replaced by, and replaces, SetRobustLoss's.
  void SetWhitenedRobustLoss(RobustLossKind kind, std::vector<double> whitened_scale);

  void Build();

  // --- Rows, as the last Build() laid them out ---
  int num_residual_blocks() const { return static_cast<int>(evaluation_order_.size()); }
  int num_residuals() const { return num_residuals_; }
  ceres::CostFunction* cost(int k) const { return evaluation_order_[k].first; }
  ceres::LossFunction* loss(int k) const { return evaluation_losses_[k]; }  // null: none
  // The parameter blocks residual block k reads, in its cost's order. Interned: blocks that
  // read the same blocks get the same list, at the same address.
  const std::vector<int>& blocks_of(int k) const { return *evaluation_order_[k].second; }
  // First row of each residual block.
  const std::vector<int>& residual_rows() const { return rows_; }
  const std::vector<ResidualInfo>& residual_infos() const { return infos_; }

  // --- Columns, as the last Build() laid them out ---
  const std::vector<FreeParameter>& free_parameters() const { return free_; }
  int num_free() const { return static_cast<int>(free_.size()); }
  // Per block, per entry: its column among the free parameters (-1: not free).
  const std::vector<std::vector<int>>& free_columns() const { return free_column_; }
  Eigen::VectorXd FreeValues() const;
  void SetFreeValues(const Eigen::VectorXd& x);
  Eigen::VectorXd LowerBounds() const;  // -inf where unbounded
  Eigen::VectorXd UpperBounds() const;  // +inf where unbounded

 private:
  struct Block {
    std::string name;
    std::vector<Parameter> params;
    std::vector<double> values;
    bool used = false;
  };
  struct Residual {
    std::unique_ptr<ceres::CostFunction> cost;
    const std::vector<int>* blocks;  // one of block_lists_
  };

  // The interned copy of `blocks` (blocks_of()).
  const std::vector<int>* InternBlocks(const std::vector<int>& blocks);
  // Build()'s steps: forget what the last Build made; each measurement's row with its robust
  // loss; the free parameters' columns and their priors' rows. AppendRow puts one residual
  // block in evaluation order.
  void ClearBuilt();
  void AddMeasurementRows();
  void AddFreeColumnsAndPriors();
  void AppendRow(ceres::CostFunction* cost, ceres::LossFunction* loss,
                 const std::vector<int>& block_ids);

  // Added: each block at a stable address (its values are read in place).
  std::vector<std::unique_ptr<Block>> blocks_;
  std::vector<Residual> residuals_;
  // Per residual block: the measurements' as added, then the priors' as Build() derives them.
  std::vector<ResidualInfo> infos_;
  // Each distinct list of parameter blocks a residual reads, once, at a stable address: a
  // recording's tens of thousands of blocks read a few dozen lists, so two blocks read the same
  // blocks exactly when they point at the same list (the layout compares pointers, not lists).
  std::deque<std::vector<int>> block_lists_;
  std::map<std::vector<int>, const std::vector<int>*> list_of_blocks_;
  std::vector<const std::vector<int>*> recent_lists_;  // InternBlocks's last few, checked first
  RobustLossKind loss_kind_ = RobustLossKind::kNone;
  double loss_scale_ = 1.0;
  std::vector<double> loss_whitened_scale_;  // per measurement block; empty: loss_scale_
  int num_measurement_residuals_ = 0;

  // Built: the rows (per residual block, in evaluation order: its cost and parameter blocks,
  // its loss, its first row), the costs and losses Build made for them, the columns.
  std::vector<std::pair<ceres::CostFunction*, const std::vector<int>*>> evaluation_order_;
  std::vector<ceres::LossFunction*> evaluation_losses_;
  std::vector<int> rows_;
  int num_residuals_ = 0;
  std::vector<std::unique_ptr<ceres::CostFunction>> prior_costs_;
  std::vector<std::unique_ptr<ceres::LossFunction>> losses_;
  std::vector<FreeParameter> free_;
  std::vector<std::vector<int>> free_column_;
};

}  // namespace cellmetry
