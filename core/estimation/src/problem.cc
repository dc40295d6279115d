// Problem (problem.h): named parameter blocks and whitened residuals rebuilt into a ceres::Problem
// with fixed entries, bounds and priors, and the free-parameter vector view other solvers use.
#include "cellmetry/estimation/problem.h"

#include <cmath>
#include <limits>

namespace cellmetry {

struct Problem::Block {
  std::string name;
  std::vector<Parameter> params;
  std::vector<double> values;
  bool used = false;
};

struct Problem::Residual {
  std::unique_ptr<ceres::CostFunction> cost;
  std::vector<int> blocks;
};

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

void Problem::AddResidual(std::unique_ptr<ceres::CostFunction> cost, std::vector<int> blocks,
                          ResidualInfo info) {
  for (int b : blocks) blocks_[b]->used = true;
  residuals_.push_back(Residual{std::move(cost), std::move(blocks)});
  infos_.push_back(std::move(info));
  num_measurement_residuals_ = static_cast<int>(residuals_.size());
}

void Problem::SetRobustLoss(RobustLossKind kind, double scale) {
  loss_kind_ = kind;
  loss_scale_ = scale;
}

void Problem::Build() {
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.enable_fast_removal = false;
  ceres_problem_ = std::make_unique<ceres::Problem>(options);
  residual_ids_.clear();
  losses_.clear();
  manifolds_.clear();
  prior_costs_.clear();
  infos_.resize(num_measurement_residuals_);  // priors are re-derived below
  rows_.clear();
  num_residuals_ = 0;

  auto add = [&](ceres::CostFunction* cost, ceres::LossFunction* loss,
                 const std::vector<int>& block_ids) {
    std::vector<double*> pointers;
    for (int b : block_ids) pointers.push_back(values(b));
    residual_ids_.push_back(ceres_problem_->AddResidualBlock(cost, loss, pointers));
    rows_.push_back(num_residuals_);
    num_residuals_ += cost->num_residuals();
  };

  for (size_t i = 0; i < residuals_.size(); ++i) {
    ceres::LossFunction* loss = nullptr;
    if (loss_kind_ != RobustLossKind::kNone) {
      const double sigma = infos_[i].sigma.norm() / std::sqrt(3.0);
      const double scale = loss_scale_ / sigma;
      if (loss_kind_ == RobustLossKind::kHuber) {
        losses_.push_back(std::make_unique<ceres::HuberLoss>(scale));
      } else {
        losses_.push_back(std::make_unique<ceres::CauchyLoss>(scale));
      }
      loss = losses_.back().get();
    }
    add(residuals_[i].cost.get(), loss, residuals_[i].blocks);
  }

  free_.clear();
  variable_blocks_.clear();
  for (size_t b = 0; b < blocks_.size(); ++b) {
    Block& block = *blocks_[b];
    if (!block.used) continue;
    std::vector<int> fixed;
    for (size_t i = 0; i < block.params.size(); ++i) {
      const Parameter& p = block.params[i];
      if (p.fixed) {
        fixed.push_back(static_cast<int>(i));
        continue;
      }
      free_.push_back({static_cast<int>(b), static_cast<int>(i), block.name + "." + p.name,
                       p.unit});
      if (p.lower) ceres_problem_->SetParameterLowerBound(block.values.data(), i, *p.lower);
      if (p.upper) ceres_problem_->SetParameterUpperBound(block.values.data(), i, *p.upper);
      if (p.prior_sigma) {
        prior_costs_.push_back(std::make_unique<PriorCost>(static_cast<int>(block.params.size()),
                                                           static_cast<int>(i), p.nominal,
                                                           *p.prior_sigma));
        add(prior_costs_.back().get(), nullptr, {static_cast<int>(b)});
        ResidualInfo info;
        info.kind = ResidualInfo::Kind::kPrior;
        info.target = block.name + "." + p.name;
        info.sigma = Eigen::Vector3d::Constant(*p.prior_sigma);
        infos_.push_back(info);
      }
    }
    if (fixed.size() == block.params.size()) {
      ceres_problem_->SetParameterBlockConstant(block.values.data());
    } else {
      if (!fixed.empty()) {
        manifolds_.push_back(std::make_unique<ceres::SubsetManifold>(
            static_cast<int>(block.params.size()), fixed));
        ceres_problem_->SetManifold(block.values.data(), manifolds_.back().get());
      }
      variable_blocks_.push_back(block.values.data());
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

bool Problem::Evaluate(double* cost, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian,
                       bool apply_loss) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = variable_blocks_;
  options.residual_blocks = residual_ids_;
  options.apply_loss_function = apply_loss;
  options.num_threads = 2;
  double local_cost = 0.0;
  std::vector<double> r;
  ceres::CRSMatrix crs;
  if (!ceres_problem_->Evaluate(options, &local_cost, residuals ? &r : nullptr, nullptr,
                                jacobian ? &crs : nullptr)) {
    return false;
  }
  if (cost) *cost = local_cost;
  if (residuals) *residuals = Eigen::Map<Eigen::VectorXd>(r.data(), r.size());
  if (jacobian) {
    jacobian->setZero(crs.num_rows, crs.num_cols);
    for (int row = 0; row < crs.num_rows; ++row) {
      for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
        (*jacobian)(row, crs.cols[k]) = crs.values[k];
      }
    }
  }
  return true;
}

Linearization Linearize(Problem& problem) {
  Linearization at;
  at.valid = problem.Evaluate(nullptr, &at.residuals, &at.jacobian, /*apply_loss=*/false);
  return at;
}

}  // namespace cellmetry
