// BlockRegistry (block_registry.h): parameter and residual blocks, and the rows, columns and
// layout Build() makes of them.
#include "cellmetry/estimation/block_registry.h"

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

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

BlockRegistry::BlockRegistry() = default;
BlockRegistry::~BlockRegistry() = default;

int BlockRegistry::AddBlock(const std::string& name, std::vector<Parameter> params) {
  auto block = std::make_unique<Block>();
  block->name = name;
  for (const auto& p : params) block->values.push_back(p.nominal);
  block->params = std::move(params);
  blocks_.push_back(std::move(block));
  return static_cast<int>(blocks_.size()) - 1;
}

int BlockRegistry::FindBlock(const std::string& name) const {
  for (size_t i = 0; i < blocks_.size(); ++i) {
    if (blocks_[i]->name == name) return static_cast<int>(i);
  }
  return -1;
}

void BlockRegistry::SetFixed(int block, int index, bool fixed) {
  blocks_[block]->params[index].fixed = fixed;
}

void BlockRegistry::SetPrior(int block, int index, double mean, double sigma) {
  Parameter& p = blocks_[block]->params[index];
  p.nominal = mean;
  p.prior_sigma = sigma;
}

void BlockRegistry::ReserveResiduals(int num_blocks) {
  residuals_.reserve(num_blocks);
  infos_.reserve(num_blocks);
}

void BlockRegistry::AddResidual(std::unique_ptr<ceres::CostFunction> cost,
                                const std::vector<int>& blocks, const ResidualInfo& info) {
  for (int b : blocks) blocks_[b]->used = true;
  residuals_.push_back(Residual{std::move(cost), InternBlocks(blocks)});
  infos_.push_back(info);
  num_measurement_residuals_ = static_cast<int>(residuals_.size());
}

const std::vector<int>* BlockRegistry::InternBlocks(const std::vector<int>& blocks) {
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

void BlockRegistry::SetRobustLoss(RobustLossKind kind, double scale) {
  loss_kind_ = kind;
  loss_scale_ = scale;
  loss_whitened_scale_.clear();
}

void BlockRegistry::SetWhitenedRobustLoss(RobustLossKind kind, std::vector<double> whitened_scale) {
  loss_kind_ = kind;
  loss_whitened_scale_ = std::move(whitened_scale);
}

void BlockRegistry::Build() {
  ClearBuilt();
  AddMeasurementRows();
  AddFreeColumnsAndPriors();
}

void BlockRegistry::ClearBuilt() {
  losses_.clear();
  prior_costs_.clear();
  infos_.resize(num_measurement_residuals_);  // priors are derived again below
  rows_.clear();
  evaluation_order_.clear();
  evaluation_losses_.clear();
  num_residuals_ = 0;
  evaluation_order_.reserve(residuals_.size());
  evaluation_losses_.reserve(residuals_.size());
  rows_.reserve(residuals_.size());
}

void BlockRegistry::AppendRow(ceres::CostFunction* cost, ceres::LossFunction* loss,
                              const std::vector<int>& block_ids) {
  evaluation_order_.emplace_back(cost, &block_ids);
  evaluation_losses_.push_back(loss);
  rows_.push_back(num_residuals_);
  num_residuals_ += cost->num_residuals();
}

void BlockRegistry::AddMeasurementRows() {
  // One loss object per scale: the blocks of a group share their scale, and 22,500 of them
  // each allocating its own was a third of a Build.
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

void BlockRegistry::AddFreeColumnsAndPriors() {
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
      free_.push_back(
          {static_cast<int>(b), static_cast<int>(i), block.name + "." + p.name, p.unit});
      if (!p.prior_sigma) continue;
      prior_costs_.push_back(std::make_unique<PriorCost>(
          static_cast<int>(block.params.size()), static_cast<int>(i), p.nominal, *p.prior_sigma));
      AppendRow(prior_costs_.back().get(), nullptr, *InternBlocks({static_cast<int>(b)}));
      ResidualInfo info;
      info.kind = ResidualInfo::Kind::kPrior;
      info.sigma = Eigen::Vector3d::Constant(*p.prior_sigma);
      infos_.push_back(info);
    }
  }
}

Eigen::VectorXd BlockRegistry::FreeValues() const {
  Eigen::VectorXd x(free_.size());
  for (size_t i = 0; i < free_.size(); ++i) x[i] = blocks_[free_[i].block]->values[free_[i].index];
  return x;
}

void BlockRegistry::SetFreeValues(const Eigen::VectorXd& x) {
  for (size_t i = 0; i < free_.size(); ++i) blocks_[free_[i].block]->values[free_[i].index] = x[i];
}

Eigen::VectorXd BlockRegistry::LowerBounds() const {
  Eigen::VectorXd lower(free_.size());
  for (size_t i = 0; i < free_.size(); ++i) {
    const auto& p = blocks_[free_[i].block]->params[free_[i].index];
    lower[i] = p.lower ? *p.lower : -std::numeric_limits<double>::infinity();
  }
  return lower;
}

Eigen::VectorXd BlockRegistry::UpperBounds() const {
  Eigen::VectorXd upper(free_.size());
  for (size_t i = 0; i < free_.size(); ++i) {
    const auto& p = blocks_[free_[i].block]->params[free_[i].index];
    upper[i] = p.upper ? *p.upper : std::numeric_limits<double>::infinity();
  }
  return upper;
}

}  // namespace cellmetry
