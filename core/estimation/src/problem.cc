// Problem (problem.h): named parameter blocks and whitened residuals rebuilt into a ceres::Problem
// with fixed entries, bounds and priors, and the free-parameter vector view other solvers use.
#include "cellmetry/estimation/problem.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>
#include <stdexcept>

#include "cellmetry/estimation/shared_prediction_cost.h"
#include "column_patterns.h"
#include "problem_blocks.h"

namespace cellmetry {

namespace {

// (x[index] - nominal) / sigma: a Gaussian prior on one entry of a block.
class PriorCost : public ceres::CostFunction {
 public:
  PriorCost(int block_size, int index, double nominal, double sigma)
      : index_(index), nominal_(nominal), sigma_(sigma) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(block_size);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    residuals[0] = (parameters[0][index_] - nominal_) / sigma_;
    if (jacobians && jacobians[0]) {
      const int size = parameter_block_sizes()[0];
      for (int i = 0; i < size; ++i) jacobians[0][i] = 0.0;
      jacobians[0][index_] = 1.0 / sigma_;
    }
    return true;
  }

 private:
  int index_;
  double nominal_;
  double sigma_;
};

}  // namespace

int FindParameter(const std::vector<Parameter>& params, const std::string& name) {
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

Problem::Problem() = default;
Problem::~Problem() = default;

int Problem::AddBlock(const std::string& name, std::vector<Parameter> params) {
  auto block = std::make_unique<Block>();
  block->name = name;
  for (const auto& p : params) block->values.push_back(p.nominal);
  block->params = std::move(params);
  blocks_.push_back(std::move(block));
  return static_cast<int>(blocks_.size()) - 1;
}

int Problem::FindBlock(const std::string& name) const {
  for (size_t i = 0; i < blocks_.size(); ++i) {
    if (blocks_[i]->name == name) return static_cast<int>(i);
  }
  return -1;
}

const std::string& Problem::block_name(int block) const { return blocks_[block]->name; }
const std::vector<Parameter>& Problem::block_parameters(int block) const {
  return blocks_[block]->params;
}
double* Problem::values(int block) { return blocks_[block]->values.data(); }
const double* Problem::values(int block) const { return blocks_[block]->values.data(); }
void Problem::SetFixed(int block, int index, bool fixed) {
  blocks_[block]->params[index].fixed = fixed;
}

void Problem::ReserveResiduals(int num_blocks) {
  residuals_.reserve(num_blocks);
  infos_.reserve(num_blocks);
}

void Problem::AddResidual(std::unique_ptr<ceres::CostFunction> cost, std::vector<int> blocks,
                          ResidualInfo info) {
  for (int b : blocks) blocks_[b]->used = true;
  residuals_.push_back(Residual{std::move(cost), InternBlocks(blocks)});
  infos_.push_back(std::move(info));
  num_measurement_residuals_ = static_cast<int>(residuals_.size());
}

const std::vector<int>* Problem::InternBlocks(const std::vector<int>& blocks) {
  for (const std::vector<int>* list : recent_lists_) {
    if (*list == blocks) return list;
  }
  const std::vector<int>*& list = list_of_blocks_[blocks];
  if (list == nullptr) list = &block_lists_.emplace_back(blocks);
  // Observations come pose by pose, each camera's and target's lists in turn: the last few
  // lists used answer nearly every call without a search.
  constexpr size_t kRecent = 8;
  if (recent_lists_.size() == kRecent) recent_lists_.erase(recent_lists_.begin());
  recent_lists_.push_back(list);
  return list;
}

void Problem::SetRobustLoss(RobustLossKind kind, double scale) {
  loss_kind_ = kind;
  loss_scale_ = scale;
  loss_whitened_scale_.clear();
}

void Problem::SetWhitenedRobustLoss(RobustLossKind kind, std::vector<double> whitened_scale) {
  loss_kind_ = kind;
  loss_whitened_scale_ = std::move(whitened_scale);
}

void Problem::Build() {
  ClearBuilt();
  AddMeasurementRows();
  AddFreeColumnsAndPriors();
  BuildSparseLayout();
}

void Problem::ClearBuilt() {
  // The Ceres views point at the losses and priors made again below: dropped first, made again
  // when a solver or Evaluate first needs them (problem_ceres.cc).
  for_evaluation_.Reset();
  for_solving_.Reset();
  losses_.clear();
  prior_costs_.clear();
  infos_.resize(num_measurement_residuals_);  // priors are re-derived below
  rows_.clear();
  evaluation_order_.clear();
  evaluation_losses_.clear();
  num_residuals_ = 0;
  evaluation_order_.reserve(residuals_.size());
  evaluation_losses_.reserve(residuals_.size());
  rows_.reserve(residuals_.size());
}

void Problem::AppendRow(ceres::CostFunction* cost, ceres::LossFunction* loss,
                        const std::vector<int>& block_ids) {
  evaluation_order_.emplace_back(cost, &block_ids);
  evaluation_losses_.push_back(loss);
  rows_.push_back(num_residuals_);
  num_residuals_ += cost->num_residuals();
}

void Problem::AddMeasurementRows() {
  // One loss object per scale: the blocks of a group share their scale (RobustScales), and
  // 22,500 of them each allocating its own was a third of a Build.
  std::map<double, ceres::LossFunction*> loss_of_scale;
  for (size_t i = 0; i < residuals_.size(); ++i) {
    ceres::LossFunction* loss = nullptr;
    double scale = 0.0;
    if (loss_whitened_scale_.empty()) {
      scale = loss_scale_ / (infos_[i].sigma.norm() / std::sqrt(3.0));
    } else if (i < loss_whitened_scale_.size()) {
      scale = loss_whitened_scale_[i];
    }
    if (loss_kind_ != RobustLossKind::kNone && std::isfinite(scale) && scale > 0.0) {
      ceres::LossFunction*& shared = loss_of_scale[scale];
      if (shared == nullptr) {
        if (loss_kind_ == RobustLossKind::kHuber) {
          losses_.push_back(std::make_unique<ceres::HuberLoss>(scale));
        } else {
          losses_.push_back(std::make_unique<ceres::CauchyLoss>(scale));
        }
        shared = losses_.back().get();
      }
      loss = shared;
    }
    AppendRow(residuals_[i].cost.get(), loss, *residuals_[i].blocks);
  }
}

void Problem::AddFreeColumnsAndPriors() {
  free_.clear();
  free_column_.assign(blocks_.size(), {});
  for (size_t b = 0; b < blocks_.size(); ++b) {
    Block& block = *blocks_[b];
    free_column_[b].assign(block.params.size(), -1);
    if (!block.used) continue;
    for (size_t i = 0; i < block.params.size(); ++i) {
      const Parameter& p = block.params[i];
      if (p.fixed) continue;
      free_column_[b][i] = static_cast<int>(free_.size());
      free_.push_back({static_cast<int>(b), static_cast<int>(i), block.name + "." + p.name,
                       p.unit});
      if (!p.prior_sigma) continue;
      prior_costs_.push_back(std::make_unique<PriorCost>(static_cast<int>(block.params.size()),
                                                         static_cast<int>(i), p.nominal,
                                                         *p.prior_sigma));
      AppendRow(prior_costs_.back().get(), nullptr, *InternBlocks({static_cast<int>(b)}));
      ResidualInfo info;
      info.kind = ResidualInfo::Kind::kPrior;
      info.target = block.name + "." + p.name;
      info.sigma = Eigen::Vector3d::Constant(*p.prior_sigma);
      infos_.push_back(info);
    }
  }
}

Eigen::VectorXd Problem::FreeValues() const {
  Eigen::VectorXd x(free_.size());
  for (size_t i = 0; i < free_.size(); ++i) x[i] = blocks_[free_[i].block]->values[free_[i].index];
  return x;
}

void Problem::SetFreeValues(const Eigen::VectorXd& x) {
  for (size_t i = 0; i < free_.size(); ++i) blocks_[free_[i].block]->values[free_[i].index] = x[i];
}

Eigen::VectorXd Problem::LowerBounds() const {
  Eigen::VectorXd lower(free_.size());
  for (size_t i = 0; i < free_.size(); ++i) {
    const auto& p = blocks_[free_[i].block]->params[free_[i].index];
    lower[i] = p.lower ? *p.lower : -std::numeric_limits<double>::infinity();
  }
  return lower;
}

Eigen::VectorXd Problem::UpperBounds() const {
  Eigen::VectorXd upper(free_.size());
  for (size_t i = 0; i < free_.size(); ++i) {
    const auto& p = blocks_[free_[i].block]->params[free_[i].index];
    upper[i] = p.upper ? *p.upper : std::numeric_limits<double>::infinity();
  }
  return upper;
}

namespace {

// Ceres's evaluation of `problem` over `blocks` (every free block, every residual block).
bool EvaluateCeres(ceres::Problem& problem, const std::vector<double*>& parameter_blocks,
                   const std::vector<ceres::ResidualBlockId>& residual_blocks, bool apply_loss,
                   double* cost, Eigen::VectorXd* residuals, ceres::CRSMatrix* crs) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = parameter_blocks;
  options.residual_blocks = residual_blocks;
  options.apply_loss_function = apply_loss;
  options.num_threads = 2;
  double local_cost = 0.0;
  std::vector<double> r;
  if (!problem.Evaluate(options, &local_cost, residuals ? &r : nullptr, nullptr, crs)) {
    return false;
  }
  if (cost) *cost = local_cost;
  if (residuals) *residuals = Eigen::Map<Eigen::VectorXd>(r.data(), r.size());
  return true;
}

}  // namespace

bool Problem::Evaluate(double* cost, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian,
                       bool apply_loss) {
  ceres::CRSMatrix crs;
  ceres::Problem& ceres = ceres_problem();
  if (!EvaluateCeres(ceres, for_evaluation_.variable_blocks, for_evaluation_.residual_ids,
                     apply_loss, cost, residuals,
                     jacobian ? &crs : nullptr)) {
    return false;
  }
  // Ceres's rows in this Problem's order (BuildCeres: units it evaluates as one block).
  auto row_of = [&](int ceres_row) {
    return for_evaluation_.rows.empty() ? ceres_row : for_evaluation_.rows[ceres_row];
  };
  if (residuals && !for_evaluation_.rows.empty()) {
    Eigen::VectorXd in_order(residuals->size());
    for (int row = 0; row < residuals->size(); ++row) in_order[row_of(row)] = (*residuals)[row];
    *residuals = std::move(in_order);
  }
  if (jacobian) {
    jacobian->setZero(crs.num_rows, crs.num_cols);
    for (int row = 0; row < crs.num_rows; ++row) {
      for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
        (*jacobian)(row_of(row), crs.cols[k]) = crs.values[k];
      }
    }
  }
  return true;
}

void Problem::BuildSparseLayout() {
  // The layout is a function of the residual blocks (appended only) and the free columns: a
  // Build that changed neither (a new robust loss, a parameter held and freed again) keeps it.
  const int num_blocks = static_cast<int>(evaluation_order_.size());
  if (layout_num_blocks_ == num_blocks && layout_free_column_ == free_column_) return;
  layout_num_blocks_ = num_blocks;
  layout_free_column_ = free_column_;
  // Each residual block's rows hold the same columns: the free entries of its blocks, in
  // column order. Blocks over the same parameter blocks (every observation of one tool by one
  // camera) have the same entries: worked out and stored once per list of blocks.
  struct Pattern {
    EntryRange entries;  // in sparse_entries_
    int group = 0;
  };
  std::unordered_map<const std::vector<int>*, Pattern> patterns_of_blocks;  // interned lists
  ColumnPatterns patterns;
  std::vector<int> columns;
  sparse_entries_.clear();
  auto pattern_of = [&](const std::vector<int>& block_ids) -> const Pattern& {
    auto [it, inserted] = patterns_of_blocks.try_emplace(&block_ids);
    Pattern& pattern = it->second;
    if (!inserted) return pattern;
    pattern.entries.begin = static_cast<int>(sparse_entries_.size());
    for (size_t slot = 0; slot < block_ids.size(); ++slot) {
      const auto& free_column = free_column_[block_ids[slot]];
      for (size_t i = 0; i < free_column.size(); ++i) {
        if (free_column[i] >= 0) {
          sparse_entries_.push_back(
              {free_column[i], static_cast<int>(slot), static_cast<int>(i)});
        }
      }
    }
    pattern.entries.end = static_cast<int>(sparse_entries_.size());
    const auto first = sparse_entries_.begin() + pattern.entries.begin;
    std::sort(first, sparse_entries_.end(),
              [](const SparseEntry& a, const SparseEntry& b) { return a.column < b.column; });
    // Column groups: the same column list, the same group.
    columns.clear();
    for (auto e = first; e != sparse_entries_.end(); ++e) columns.push_back(e->column);
    pattern.group = patterns.GroupOf(columns.data(), static_cast<int>(columns.size()));
    return pattern;
  };
  block_entries_.resize(num_blocks);
  sparse_row_start_.assign(num_residuals_ + 1, 0);
  column_group_.assign(num_blocks, 0);
  for (int k = 0; k < num_blocks; ++k) {
    const std::vector<int>& block_ids = *evaluation_order_[k].second;
    // Blocks come in runs over the same parameter blocks: the previous one's, without a lookup.
    const bool as_previous = k > 0 && &block_ids == evaluation_order_[k - 1].second;
    if (as_previous) {
      block_entries_[k] = block_entries_[k - 1];
      column_group_[k] = column_group_[k - 1];
    } else {
      const Pattern& pattern = pattern_of(block_ids);
      block_entries_[k] = pattern.entries;
      column_group_[k] = pattern.group;
    }
    const int width = block_entries_[k].end - block_entries_[k].begin;
    const int num_rows = evaluation_order_[k].first->num_residuals();
    for (int row = 0; row < num_rows; ++row) sparse_row_start_[rows_[k] + row + 1] = width;
  }
  for (int row = 0; row < num_residuals_; ++row) {
    sparse_row_start_[row + 1] += sparse_row_start_[row];
  }
  group_columns_ = patterns.groups();
  BuildPredictionUnits();
}

void Problem::PrepareSlots(int k, int num_rows, bool with_jacobians,
                           BlockEvaluation* scratch) const {
  const std::vector<int>& block_ids = *evaluation_order_[k].second;
  scratch->parameters.clear();
  scratch->jacobians.resize(block_ids.size());
  scratch->pointers.assign(block_ids.size(), nullptr);
  scratch->asked.resize(block_ids.size(), 0);
  for (size_t slot = 0; slot < block_ids.size(); ++slot) {
    scratch->parameters.push_back(values(block_ids[slot]));
    if (!with_jacobians || !scratch->asked[slot]) continue;  // not differentiated
    scratch->jacobians[slot].resize(static_cast<size_t>(num_rows) *
                                    blocks_[block_ids[slot]]->params.size());
    scratch->pointers[slot] = scratch->jacobians[slot].data();
  }
}

bool Problem::EvaluateBlock(int k, bool with_jacobians, BlockEvaluation* scratch) const {
  ceres::CostFunction* cost = evaluation_order_[k].first;
  const int num_rows = cost->num_residuals();
  PrepareSlots(k, num_rows, with_jacobians, scratch);
  scratch->residuals.resize(num_rows);
  return cost->Evaluate(scratch->parameters.data(), scratch->residuals.data(),
                        with_jacobians ? scratch->pointers.data() : nullptr);
}

int Problem::GatherFreeColumns(int k, int num_rows, const BlockEvaluation& scratch,
                               std::vector<double>* rows) const {
  const std::vector<int>& block_ids = *evaluation_order_[k].second;
  const int first = block_entries_[k].begin;
  const int width = block_entries_[k].end - first;
  rows->resize(static_cast<size_t>(num_rows) * width);
  for (int j = 0; j < width; ++j) {
    const SparseEntry& e = sparse_entries_[first + j];
    const int block_width = static_cast<int>(blocks_[block_ids[e.slot]]->params.size());
    for (int row = 0; row < num_rows; ++row) {
      (*rows)[row * width + j] = scratch.At(e.slot, row, block_width, e.index);
    }
  }
  return width;
}

void Problem::AskFreeSlots(int k, BlockEvaluation* scratch) const {
  scratch->asked.assign(evaluation_order_[k].second->size(), 0);
  for (int e = block_entries_[k].begin; e < block_entries_[k].end; ++e) {
    scratch->asked[sparse_entries_[e].slot] = 1;
  }
}

bool Problem::EvaluateBlockRows(int u, BlockEvaluation* scratch, const SparseOutput& out) const {
  const int k = unit_blocks_[unit_start_[u]];
  const bool with_jacobian = out.column_index != nullptr || out.gram != nullptr;
  AskFreeSlots(k, scratch);
  if (!EvaluateBlock(k, with_jacobian, scratch)) return false;
  std::copy(scratch->residuals.begin(), scratch->residuals.end(), out.r + rows_[k]);
  const int num_rows = static_cast<int>(scratch->residuals.size());
  if (out.column_index) {
    WriteBlockRows(k, *scratch, &sparse_row_start_[rows_[k]], out.column_index, out.entries);
  }
  if (out.gram) {  // a block alone stands for itself
    const int first = out.gram_unit_row[u];
    WriteBlockRows(k, *scratch, out.gram->rows.outerIndexPtr() + first,
                   out.gram->rows.innerIndexPtr(), out.gram->rows.valuePtr());
    for (int row = 0; row < num_rows; ++row) out.gram->block[static_cast<size_t>(first + row)] = k;
  }
  return true;
}

void Problem::WriteBlockRows(int k, const BlockEvaluation& scratch, const int* row_start,
                             int* column_index, double* entries) const {
  const std::vector<int>& block_ids = *evaluation_order_[k].second;
  const int num_rows = static_cast<int>(scratch.residuals.size());
  for (int row = 0; row < num_rows; ++row) {
    int at = row_start[row];
    for (int k_e = block_entries_[k].begin; k_e < block_entries_[k].end; ++k_e) {
      const SparseEntry& e = sparse_entries_[k_e];
      const int width = static_cast<int>(blocks_[block_ids[e.slot]]->params.size());
      column_index[at] = e.column;
      entries[at++] = scratch.At(e.slot, row, width, e.index);
    }
  }
}

int Problem::NumGramRows(std::vector<int>* unit_row) const {
  const int num_units = static_cast<int>(unit_start_.size()) - 1;
  if (unit_row) unit_row->assign(static_cast<size_t>(num_units) + 1, 0);
  int total = 0;
  for (int u = 0; u < num_units; ++u) {
    const int k = unit_blocks_[unit_start_[u]];
    const int end = k + 1 < static_cast<int>(rows_.size()) ? rows_[k + 1] : num_residuals_;
    total += SharesPrediction(u) ? 3 : end - rows_[k];
    if (unit_row) (*unit_row)[static_cast<size_t>(u) + 1] = total;
  }
  return total;
}

// Where few captures share a prediction the rows are mostly J's own: J itself serves (GramOf).
// bench_scale's factory cell (one capture per pose, its world tags shared) would have half of
// J's rows, and its BM_Linearize took 29 ms instead of 16.
bool Problem::HasGramRows() const { return 4 * NumGramRows(nullptr) <= num_residuals_; }

std::vector<int> Problem::LayOutGramRows(GramRows* gram) const {
  *gram = GramRows{};
  if (!HasGramRows()) return {};
  const int num_units = static_cast<int>(unit_start_.size()) - 1;
  std::vector<int> unit_row;
  const int num_rows = NumGramRows(&unit_row);
  int entries = 0;
  for (int u = 0; u < num_units; ++u) {
    const int k = unit_blocks_[unit_start_[u]];
    entries += (unit_row[u + 1] - unit_row[u]) * (block_entries_[k].end - block_entries_[k].begin);
  }
  gram->rows.resize(num_rows, num_free());
  gram->rows.resizeNonZeros(entries);
  gram->block.assign(static_cast<size_t>(num_rows), -1);
  gram->row_of_block.assign(evaluation_order_.size(), -1);
  int* starts = gram->rows.outerIndexPtr();
  starts[0] = 0;
  for (int u = 0; u < num_units; ++u) {
    const int k = unit_blocks_[unit_start_[u]];
    const int width = block_entries_[k].end - block_entries_[k].begin;
    for (int row = unit_row[u]; row < unit_row[u + 1]; ++row) starts[row + 1] = starts[row] + width;
    for (int i = unit_start_[u]; i < unit_start_[u + 1]; ++i) {
      gram->row_of_block[static_cast<size_t>(unit_blocks_[i])] = unit_row[u];
    }
  }
  return unit_row;
}

bool Problem::EvaluateSparse(Eigen::VectorXd* residuals, SparseJacobian* jacobian,
                             GramRows* gram) const {
  const std::vector<int>& row_start = sparse_row_start_;
  // Written in place into the compressed row storage (no triplets, no copy of a map).
  int* column_index = nullptr;
  double* entries = nullptr;
  if (jacobian) {
    jacobian->resize(num_residuals_, num_free());
    jacobian->resizeNonZeros(row_start.back());
    std::copy(row_start.begin(), row_start.end(), jacobian->outerIndexPtr());
    column_index = jacobian->innerIndexPtr();
    entries = jacobian->valuePtr();
  }
  std::vector<int> gram_unit_row;
  if (gram) gram_unit_row = LayOutGramRows(gram);
  if (gram && !jacobian && gram_unit_row.empty()) {
    throw std::logic_error("EvaluateSparse: Gram rows alone asked of a problem without them");
  }
  Eigen::VectorXd r(num_residuals_);
  const SparseOutput out{r.data(), column_index, entries,
                         gram_unit_row.empty() ? nullptr : gram, gram_unit_row.data()};
  const int num_chunks = static_cast<int>(chunk_start_.size()) - 1;
  std::atomic<bool> valid{true};
  tbb::parallel_for(tbb::blocked_range<int>(0, num_chunks, 1), [&](const auto& chunks) {
    BlockEvaluation scratch;
    for (int u = chunk_start_[chunks.begin()]; u != chunk_start_[chunks.end()] && valid; ++u) {
      const bool ok = SharesPrediction(u) ? EvaluateSharedRows(u, &scratch, out)
                                          : EvaluateBlockRows(u, &scratch, out);
      if (!ok) valid = false;
    }
  });
  if (!valid) {
    if (jacobian) jacobian->setZero();
    return false;
  }
  if (residuals) *residuals = std::move(r);
  return true;
}

namespace {

// Where a residual block's Jacobian entries go: (column, parameter block of the residual, entry
// in it), in column order.
struct ColumnEntry {
  int column, slot, index;
  bool operator<(const ColumnEntry& other) const { return column < other.column; }
};

// Per residual block, the entries of the asked-for blocks' free columns (`renumbered`: free
// column -> output column, -1 when not asked for); `row_start`: each row's first entry.
struct ColumnLayout {
  std::vector<std::vector<ColumnEntry>> entries_of;
  std::vector<int> row_start;
};

ColumnLayout LayOutColumns(
    const std::vector<std::pair<ceres::CostFunction*, const std::vector<int>*>>& evaluation_order,
    const std::vector<std::vector<int>>& free_column, const std::vector<int>& first_row,
    int num_residuals, const std::vector<bool>& asked, const std::vector<int>& renumbered) {
  ColumnLayout out;
  out.entries_of.resize(evaluation_order.size());
  out.row_start.assign(num_residuals + 1, 0);
  for (size_t k = 0; k < evaluation_order.size(); ++k) {
    const auto& [cost, ids] = evaluation_order[k];
    const std::vector<int>& block_ids = *ids;
    for (size_t slot = 0; slot < block_ids.size(); ++slot) {
      if (!asked[block_ids[slot]]) continue;
      const auto& columns = free_column[block_ids[slot]];
      for (size_t i = 0; i < columns.size(); ++i) {
        if (columns[i] < 0) continue;
        out.entries_of[k].push_back(
            {renumbered[columns[i]], static_cast<int>(slot), static_cast<int>(i)});
      }
    }
    std::sort(out.entries_of[k].begin(), out.entries_of[k].end());
    for (int row = 0; row < cost->num_residuals(); ++row) {
      out.row_start[first_row[k] + row + 1] = static_cast<int>(out.entries_of[k].size());
    }
  }
  for (int row = 0; row < num_residuals; ++row) out.row_start[row + 1] += out.row_start[row];
  return out;
}

}  // namespace

bool Problem::EvaluateSparseColumns(const std::vector<int>& blocks, SparseJacobian* jacobian,
                                    std::vector<int>* columns) const {
  std::vector<bool> asked(blocks_.size(), false);
  for (int b : blocks) asked.at(b) = true;
  std::vector<int> renumbered(free_.size(), -1);
  columns->clear();
  for (size_t c = 0; c < free_.size(); ++c) {
    if (!asked[free_[c].block]) continue;
    renumbered[c] = static_cast<int>(columns->size());
    columns->push_back(static_cast<int>(c));
  }
  const ColumnLayout layout =
      LayOutColumns(evaluation_order_, free_column_, rows_, num_residuals_, asked, renumbered);
  std::vector<int> column_index(static_cast<size_t>(layout.row_start.back()));
  std::vector<double> entries(column_index.size());
  std::atomic<bool> valid{true};
  const int num_blocks = static_cast<int>(evaluation_order_.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, num_blocks, 64), [&](const auto& range) {
    BlockEvaluation scratch;
    for (int k = range.begin(); k != range.end() && valid; ++k) {
      if (layout.entries_of[k].empty()) continue;  // reads none of the blocks asked for
      const std::vector<int>& block_ids = *evaluation_order_[k].second;
      scratch.asked.resize(block_ids.size());
      for (size_t slot = 0; slot < block_ids.size(); ++slot) {
        scratch.asked[slot] = asked[block_ids[slot]];
      }
      if (!EvaluateBlock(k, true, &scratch)) {
        valid = false;
        break;
      }
      const int num_rows = static_cast<int>(scratch.residuals.size());
      for (int row = 0; row < num_rows; ++row) {
        int at = layout.row_start[rows_[k] + row];
        for (const ColumnEntry& e : layout.entries_of[k]) {
          const int width = static_cast<int>(blocks_[block_ids[e.slot]]->params.size());
          column_index[at] = e.column;
          entries[at++] = scratch.At(e.slot, row, width, e.index);
        }
      }
    }
  });
  if (!valid) return false;
  *jacobian = Eigen::Map<const SparseJacobian>(
      num_residuals_, static_cast<Eigen::Index>(columns->size()),
      static_cast<Eigen::Index>(entries.size()), layout.row_start.data(), column_index.data(),
      entries.data());
  return true;
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
