// `nlopt`: any NLopt algorithm on f(x) = 0.5 |r(x)|^2, gradient J^T r from the assembled problem.
//
// The optimiser works on scaled variables z = (x - x0) * c, with c_j = |J_j| the column norms of
// the whitened Jacobian at the start: a unit step in z changes the residuals by about one sigma
// whatever the parameter's unit, which gradient-free methods (LN_*) need to take sensible steps
// and which makes xtol meaningful for mm and rad alike. Gradient-free algorithms get box bounds
// of +-`box` around the start when the problem gives none.
#include <nlopt.hpp>

#include <chrono>
#include <cmath>

#include "cellmetry/estimation/problem.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry::nlopt_solver {
namespace {

struct Options {
  std::string algorithm = "LD_LBFGS";
  double xtol_abs = 1e-9;  // in scaled units (sigma-steps)
  double ftol_rel = 1e-15;
  int max_evaluations = 20000;
  double initial_step = 10.0;  // scaled units
  double box = 1e5;            // scaled units, for gradient-free algorithms without bounds
};

struct Context {
  Problem* problem;
  Eigen::VectorXd x0;
  Eigen::VectorXd scale;
  int evaluations = 0;
  bool failed = false;
};

double Objective(unsigned n, const double* z, double* grad, void* data) {
  auto* c = static_cast<Context*>(data);
  const Eigen::Map<const Eigen::VectorXd> zv(z, n);
  c->problem->SetFreeValues(c->x0 + zv.cwiseQuotient(c->scale));
  double cost = 0.0;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  ++c->evaluations;
  if (!c->problem->Evaluate(&cost, grad ? &r : nullptr, grad ? &J : nullptr)) {
    c->failed = true;
    return HUGE_VAL;
  }
  if (grad) {
    const Eigen::VectorXd g = (J.transpose() * r).cwiseQuotient(c->scale);
    for (unsigned i = 0; i < n; ++i) grad[i] = g[i];
  }
  return cost;
}

class NloptSolver : public Solver {
 public:
  NloptSolver(Options options, nlopt::algorithm algorithm)
      : options_(options), algorithm_(algorithm) {}

  SolverSummary Solve(Problem& problem) override {
    const auto start = std::chrono::steady_clock::now();
    SolverSummary summary;
    summary.solver = "nlopt:" + options_.algorithm;
    const unsigned n = problem.num_free();
    Context context{&problem, problem.FreeValues(), Eigen::VectorXd::Ones(n)};
    Eigen::MatrixXd J;
    problem.Evaluate(&summary.initial_cost, nullptr, &J);
    if (n == 0) {
      summary.final_cost = summary.initial_cost;
      summary.converged = true;
      summary.stop_reason = "nothing to solve: no free parameter";
      return summary;
    }
    for (unsigned j = 0; j < n; ++j) context.scale[j] = std::max(J.col(j).norm(), 1e-12);

    nlopt::opt opt(algorithm_, n);
    opt.set_min_objective(Objective, &context);
    const Eigen::VectorXd lower = problem.LowerBounds(), upper = problem.UpperBounds();
    const bool gradient_free = options_.algorithm.size() > 1 && options_.algorithm[1] == 'N';
    std::vector<double> lz(n), uz(n);
    for (unsigned j = 0; j < n; ++j) {
      lz[j] = std::isfinite(lower[j]) ? (lower[j] - context.x0[j]) * context.scale[j]
                                      : (gradient_free ? -options_.box : -HUGE_VAL);
      uz[j] = std::isfinite(upper[j]) ? (upper[j] - context.x0[j]) * context.scale[j]
                                      : (gradient_free ? options_.box : HUGE_VAL);
    }
    opt.set_lower_bounds(lz);
    opt.set_upper_bounds(uz);
    opt.set_xtol_abs(options_.xtol_abs);
    opt.set_ftol_rel(options_.ftol_rel);
    opt.set_maxeval(options_.max_evaluations);
    if (gradient_free) opt.set_initial_step(options_.initial_step);

    std::vector<double> z(n, 0.0);
    double best = 0.0;
    nlopt::result result = nlopt::FAILURE;
    try {
      result = opt.optimize(z, best);
      summary.stop_reason = nlopt_result_to_string(static_cast<nlopt_result>(result));
    } catch (const nlopt::roundoff_limited&) {
      result = nlopt::SUCCESS;  // at machine precision: as good as it gets
      summary.stop_reason = "ROUNDOFF_LIMITED";
    } catch (const std::exception& e) {
      summary.stop_reason = std::string("failed: ") + e.what();
    }
    const Eigen::Map<const Eigen::VectorXd> zv(z.data(), n);
    problem.SetFreeValues(context.x0 + zv.cwiseQuotient(context.scale));
    problem.Evaluate(&summary.final_cost, nullptr, nullptr);
    summary.evaluations = context.evaluations;
    summary.iterations = context.evaluations;
    summary.converged =
        !context.failed && (result == nlopt::SUCCESS || result == nlopt::FTOL_REACHED ||
                            result == nlopt::XTOL_REACHED || result == nlopt::STOPVAL_REACHED);
    summary.time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  }

 private:
  Options options_;
  nlopt::algorithm algorithm_;
};

std::unique_ptr<Solver> Create(const ConfigNode& config) {
  config.ExpectKeys(
      {"type", "algorithm", "xtol_abs", "ftol_rel", "max_evaluations", "initial_step", "box"});
  Options o;
  o.algorithm = config.GetString("algorithm", o.algorithm);
  // NLopt takes a negative tolerance or step without a word (and stops at once or never).
  o.xtol_abs = config.GetDoubleIn("xtol_abs", o.xtol_abs, 0, 1e3,
                                  "A step in sigma-scaled units, 0 or more: 1e-9");
  o.ftol_rel =
      config.GetDoubleIn("ftol_rel", o.ftol_rel, 0, 1, "A relative cost change, 0 or more");
  o.max_evaluations = config.GetIntIn("max_evaluations", o.max_evaluations, 1, 100000000,
                                      "Allow at least one evaluation");
  o.initial_step = config.GetDoubleIn("initial_step", o.initial_step, 1e-12, 1e6,
                                      "A first step in sigma-scaled units, above 0: 10");
  o.box = config.GetDoubleIn("box", o.box, 1e-12, 1e12,
                             "The search box's half-width in sigma-scaled units, above 0: 1e5");
  // By name over the valid algorithms: nlopt_algorithm_from_string answers an unknown name with
  // -1 in an nlopt_algorithm, a value the enum cannot hold (UBSan: invalid enum load), and the
  // compiler may then drop the `< 0` test that was to catch it.
  int algorithm = -1;
  for (int a = 0; a < NLOPT_NUM_ALGORITHMS; ++a) {
    const char* name = nlopt_algorithm_to_string(static_cast<nlopt_algorithm>(a));
    if (name && o.algorithm == name) algorithm = a;
  }
  if (algorithm < 0) {
    throw(config.Has("algorithm") ? config["algorithm"] : config)
        .Error("unknown NLopt algorithm '" + o.algorithm + "'",
               "Use an NLopt name such as LD_LBFGS, LD_SLSQP, LN_BOBYQA, LN_NELDERMEAD, LN_SBPLX");
  }
  return std::make_unique<NloptSolver>(o, static_cast<nlopt::algorithm>(algorithm));
}

}  // namespace
}  // namespace cellmetry::nlopt_solver

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "nlopt";
  info.description = "any NLopt algorithm (gradient-based LD_* or derivative-free LN_*)";
  info.options = {
      {"algorithm", "", "LD_LBFGS", "NLopt algorithm name"},
      {"xtol_abs", "sigma", "1e-9", "stop when steps are below, in sigma-scaled units"},
      {"ftol_rel", "", "1e-15", "stop when the relative cost change is below"},
      {"max_evaluations", "", "20000", "evaluation limit"},
      {"initial_step", "sigma", "10", "first step of gradient-free algorithms"},
      {"box", "sigma", "1e5", "box half-width for gradient-free algorithms without bounds"},
  };
  registry->AddSolver(info, &cellmetry::nlopt_solver::Create);
}
