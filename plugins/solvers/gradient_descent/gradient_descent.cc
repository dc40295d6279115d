// `gradient_descent`: full-batch Adam on the mean squared whitened residual, to reproduce the
// "machine learning" calibrations (PyTorch, Adam, loss = mean error, N epochs) on the same
// assembled Problem that Levenberg-Marquardt solves, so the two can be compared.
//
// Loss: L(x) = 0.5 |r(x)|^2 / m, m = number of residual rows, i.e. the mean over rows as a
// PyTorch MSE loss takes it. Its gradient J^T r / m is exact (the Problem's dense Jacobian), and
// one epoch is one full-batch step. The mean only rescales the gradient: Adam's step is invariant
// to that apart from `epsilon`, and the reported costs are the solver contract's 0.5 |r|^2.
// (A loss of mean unsquared distances, as some reports train, has another minimum; the squared
// form keeps LM's, so a comparison measures the optimiser, not the loss.)
//
// Adam works on scaled variables z = (x - x0) * c, c_j = |J_j| / sqrt(m) the root mean square
// of the whitened Jacobian's column j at the start: a unit change of z_j moves the residual rows
// by one sigma RMS whatever the parameter's unit, so one learning rate serves mm and rad alike.
// (`nlopt` scales by |J_j| itself; the RMS keeps the learning rate's meaning independent of how
// many measurements there are, as the mean loss does.) Adam's step in each z_j is roughly
// bounded by `learning_rate` (Kingma & Ba, sec. 2.1), so the learning rate is a step length in
// these sigma units: the default 1e-3 is PyTorch's and travels only a few sigma in 5000 epochs;
// a start far from the answer wants about 1.
// Bounds of the Problem are kept by clamping after each step.
//
// The Problem is left at the lowest-cost values seen: with a constant learning rate Adam
// circles the minimum rather than settling on it.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <type_traits>

#include "cellmetry/estimation/problem.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry::gradient_descent {
namespace {

struct Options {
  double learning_rate = 1e-3;    // Adam's alpha, in scaled units (sigma) per epoch
  int epochs = 5000;              // full-batch gradient steps
  double beta1 = 0.9;             // decay of the gradient's running mean
  double beta2 = 0.999;           // decay of the squared gradient's running mean
  double epsilon = 1e-8;          // keeps the step finite where the gradient vanishes
  double gradient_tolerance = 0;  // stop when |grad L|_inf (scaled) is below; 0 = off
  double cost_tolerance = 0;      // stop when 0.5 |r|^2 is below; 0 = off
};

std::string Format(const char* format, double a, double b) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
}

// Adam, Kingma & Ba, "Adam: A Method for Stochastic Optimization", ICLR 2015, Algorithm 1.
class Adam {
 public:
  Adam(const Options& options, Eigen::Index n)
      : o_(options), m_(Eigen::VectorXd::Zero(n)), v_(Eigen::VectorXd::Zero(n)) {}

  // The change of the variables for gradient `g` (theta_t = theta_{t-1} + Step(g_t)).
  Eigen::VectorXd Step(const Eigen::VectorXd& g) {
    ++t_;
    m_ = o_.beta1 * m_ + (1.0 - o_.beta1) * g;
    v_ = o_.beta2 * v_ + (1.0 - o_.beta2) * g.cwiseAbs2();
    const Eigen::VectorXd m_hat = m_ / (1.0 - std::pow(o_.beta1, t_));
    const Eigen::VectorXd v_hat = v_ / (1.0 - std::pow(o_.beta2, t_));
    return -o_.learning_rate *
           m_hat.cwiseQuotient((v_hat.cwiseSqrt().array() + o_.epsilon).matrix());
  }

 private:
  const Options o_;
  Eigen::VectorXd m_, v_;  // running means of the gradient and of its square
  int t_ = 0;
};

// The current point of the descent: values, 0.5 |r|^2, residuals and Jacobian there.
struct Point {
  Eigen::VectorXd x;
  double cost = 0.0;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
};

class GradientDescent : public Solver {
 public:
  explicit GradientDescent(Options options) : options_(options) {}

  SolverSummary Solve(Problem& problem) override {
    const auto start = std::chrono::steady_clock::now();
    SolverSummary summary;
    summary.solver = "gradient_descent";
    Point point;
    point.x = problem.FreeValues();
    if (!problem.Evaluate(&point.cost, &point.r, &point.J)) {
      summary.stop_reason = "a residual could not be evaluated at the start";
    } else if (problem.num_free() == 0) {
      summary.evaluations = 1;
      summary.initial_cost = summary.final_cost = point.cost;
      summary.converged = true;
      summary.stop_reason = "nothing to solve: no free parameter";
    } else {
      summary.evaluations = 1;
      summary.initial_cost = point.cost;
      Train(problem, point, &summary);
    }
    summary.time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  }

 private:
  // A tolerance met at `point`, as a stop reason; "" when none is (or both are off).
  std::string ToleranceMet(const Point& point, const Eigen::VectorXd& gradient) const {
    if (options_.cost_tolerance > 0 && point.cost < options_.cost_tolerance) {
      return Format("cost %.4g < cost_tolerance %.3g", point.cost, options_.cost_tolerance);
    }
    const double g_inf = gradient.lpNorm<Eigen::Infinity>();
    if (options_.gradient_tolerance > 0 && g_inf < options_.gradient_tolerance) {
      return Format("|gradient|_inf %.4g < gradient_tolerance %.3g (scaled)", g_inf,
                    options_.gradient_tolerance);
    }
    return "";
  }

  // Runs the epochs from the evaluated start `point` and leaves the Problem at the best values.
  void Train(Problem& problem, Point& point, SolverSummary* summary) const {
    const Eigen::VectorXd lower = problem.LowerBounds(), upper = problem.UpperBounds();
    const double rows = static_cast<double>(point.r.size());
    // A parameter no residual depends on has no gradient and stays; scale 1 avoids 0 / 0.
    const Eigen::VectorXd scale =
        (point.J.colwise().norm().transpose() / std::sqrt(rows)).unaryExpr([](double c) {
          return c > 0.0 ? c : 1.0;
        });
    Adam adam(options_, scale.size());
    Eigen::VectorXd best_x = point.x;
    double best_cost = point.cost;
    int best_epoch = 0;
    summary->stop_reason = std::to_string(options_.epochs) + " epochs done (limit)";
    for (int epoch = 1;; ++epoch) {
      const Eigen::VectorXd g = (point.J.transpose() * point.r / rows).cwiseQuotient(scale);
      const std::string met = ToleranceMet(point, g);
      if (!met.empty()) {
        summary->converged = true;
        summary->stop_reason = met;
        break;
      }
      if (epoch > options_.epochs) break;
      point.x = (point.x + adam.Step(g).cwiseQuotient(scale)).cwiseMax(lower).cwiseMin(upper);
      problem.SetFreeValues(point.x);
      if (!problem.Evaluate(&point.cost, &point.r, &point.J) || !std::isfinite(point.cost)) {
        summary->stop_reason = "residuals could not be evaluated at epoch " +
                               std::to_string(epoch) + "; try a smaller learning_rate";
        break;
      }
      ++summary->evaluations;
      summary->iterations = epoch;
      if (point.cost < best_cost) {
        best_cost = point.cost;
        best_x = point.x;
        best_epoch = epoch;
      }
    }
    if (best_epoch != summary->iterations) {
      summary->stop_reason += "; kept epoch " + std::to_string(best_epoch) + ", the lowest cost";
    }
    problem.SetFreeValues(best_x);
    summary->final_cost = best_cost;
  }

  Options options_;
};

// Reads a number under `key` that must satisfy `ok`; otherwise an error saying what to use.
template <typename T, typename Ok>
T Checked(const ConfigNode& config, const std::string& key, T fallback, Ok ok,
          const std::string& rule, const std::string& hint) {
  if (!config.Has(key)) return fallback;
  const ConfigNode node = config[key];
  T value;
  if constexpr (std::is_same_v<T, int>) {
    value = node.AsInt();
  } else {
    value = node.AsDouble();
  }
  if (!ok(value)) throw node.Error(rule + ", got " + node.AsString(), hint);
  return value;
}

std::unique_ptr<Solver> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "learning_rate", "epochs", "beta1", "beta2", "epsilon",
                     "gradient_tolerance", "cost_tolerance"});
  const auto positive = [](double v) { return v > 0; };
  const auto non_negative = [](double v) { return v >= 0; };
  const auto unit = [](double v) { return v >= 0 && v < 1; };
  Options o;
  o.learning_rate = Checked(config, "learning_rate", o.learning_rate, positive, "must be positive",
                            "Use a step in sigma-scaled units, e.g. 1e-3 (default) to 1");
  o.epochs = Checked(config, "epochs", o.epochs, positive, "must be at least 1",
                     "Use a whole number of full-batch steps, e.g. 5000 (default)");
  o.beta1 = Checked(config, "beta1", o.beta1, unit, "must be in [0, 1)", "Use 0.9 (default)");
  o.beta2 = Checked(config, "beta2", o.beta2, unit, "must be in [0, 1)", "Use 0.999 (default)");
  o.epsilon =
      Checked(config, "epsilon", o.epsilon, positive, "must be positive", "Use 1e-8 (default)");
  o.gradient_tolerance = Checked(config, "gradient_tolerance", o.gradient_tolerance, non_negative,
                                 "must not be negative", "Use 0 (off) or e.g. 1e-8");
  o.cost_tolerance = Checked(config, "cost_tolerance", o.cost_tolerance, non_negative,
                             "must not be negative", "Use 0 (off) or e.g. 1e-14");
  return std::make_unique<GradientDescent>(o);
}

}  // namespace
}  // namespace cellmetry::gradient_descent

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "gradient_descent";
  info.description = "full-batch Adam on the mean squared residual, as ML calibrations train";
  info.options = {
      {"learning_rate", "sigma", "1e-3", "Adam step size, in sigma-scaled units per epoch"},
      {"epochs", "", "5000", "number of full-batch gradient steps"},
      {"beta1", "", "0.9", "decay of the running gradient mean, in [0, 1)"},
      {"beta2", "", "0.999", "decay of the running squared-gradient mean, in [0, 1)"},
      {"epsilon", "", "1e-8", "added to the root mean square gradient"},
      {"gradient_tolerance", "sigma", "0", "stop when |gradient|_inf (scaled) is below; 0 = off"},
      {"cost_tolerance", "", "0", "stop when 0.5 |r|^2 is below; 0 = off"},
  };
  registry->AddSolver(info, &cellmetry::gradient_descent::Create);
}
