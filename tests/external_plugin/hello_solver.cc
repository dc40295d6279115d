// `hello_gradient`: a deliberately small solver plugin built outside the cellmetry tree.
//
// Plain gradient descent on 0.5 * |r|^2 through Problem::Evaluate: step along -J^T r, doubling the
// step length after a step that lowered the cost and halving it after one that did not.
#include <Eigen/Core>
#include <memory>

#include "cellmetry/estimation/problem.h"
#include "cellmetry/registry/registry.h"

namespace {

class HelloGradient : public cellmetry::Solver {
 public:
  explicit HelloGradient(int max_iterations) : max_iterations_(max_iterations) {}

  cellmetry::SolverSummary Solve(cellmetry::Problem& problem) override {
    cellmetry::SolverSummary summary;
    summary.solver = "hello_gradient";
    summary.stop_reason = "iteration limit reached";
    const Eigen::VectorXd lower = problem.LowerBounds(), upper = problem.UpperBounds();
    Eigen::VectorXd x = problem.FreeValues(), r;
    Eigen::MatrixXd J;
    double cost = 0.0, step = 1e-3;
    if (!problem.Evaluate(&cost, &r, &J)) {
      summary.stop_reason = "a residual could not be evaluated";
      return summary;
    }
    summary.initial_cost = summary.final_cost = cost;
    summary.evaluations = 1;
    for (int it = 0; it < max_iterations_ && problem.num_free() > 0; ++it) {
      const Eigen::VectorXd trial =
          (x - step * (J.transpose() * r)).cwiseMax(lower).cwiseMin(upper);
      problem.SetFreeValues(trial);
      double trial_cost = 0.0;
      ++summary.evaluations;
      if (problem.Evaluate(&trial_cost, nullptr, nullptr) && trial_cost < cost) {
        x = trial;
        step *= 2.0;
        problem.Evaluate(&cost, &r, &J);
      } else {
        step *= 0.5;
      }
      summary.iterations = it + 1;
      if (step < 1e-20) {
        summary.converged = true;
        summary.stop_reason = "no downhill step left";
        break;
      }
    }
    problem.SetFreeValues(x);
    summary.final_cost = cost;
    return summary;
  }

 private:
  int max_iterations_;
};

}  // namespace

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "hello_gradient";
  info.description = "plain gradient descent (example of a plugin built outside cellmetry)";
  info.options = {{"max_iterations", "", "200", "iteration limit"}};
  registry->AddSolver(
      info, [](const cellmetry::ConfigNode& config) -> std::unique_ptr<cellmetry::Solver> {
        config.ExpectKeys({"type", "max_iterations"});
        const int max_iterations = config.GetInt("max_iterations", 200);
        if (max_iterations < 1) throw config["max_iterations"].Error("must be at least 1");
        return std::make_unique<HelloGradient>(max_iterations);
      });
}
