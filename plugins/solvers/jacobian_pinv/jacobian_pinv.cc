// `jacobian_pinv`: the 2020 workcell paper's identification (Huczala et al., eq. 7-14).
//
//   dx = J^+ dY,   x_{j+1} = x_j + dx
//
// with dY = measurement - prediction = -r and J^+ the pseudo-inverse from the SVD of J, singular
// values below `rcond` times the largest dropped (the paper inverts J^T J, eq. 13, which squares
// the condition number and fails on rank deficiency). This is undamped Gauss-Newton: each step is
// clipped to max_step_mm / max_step_rad per parameter, and it stops when the largest step falls
// below step_tolerance (in mm or rad) or after max_iterations.
#include <Eigen/Dense>
#include <chrono>
#include <cmath>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/estimation/problem.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry::jacobian_pinv {
namespace {

struct Options {
  int max_iterations = 100;
  double max_step_mm = 100.0;
  double max_step_rad = 0.5;
  double step_tolerance = 1e-10;
  double rcond = 1e-12;
};

// -J^+ r through the R factor of J (J = QR, J^+ = R^+ Q^T), cheaper than an SVD of tall J.
Eigen::VectorXd PseudoInverseStep(const Eigen::MatrixXd& J, const Eigen::VectorXd& r,
                                  double rcond) {
  const Eigen::Index n = J.cols();
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(J);
  const Eigen::VectorXd qtr = (qr.householderQ().transpose() * r).head(n);
  const Eigen::MatrixXd R = qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd& s = svd.singularValues();
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (s[i] > rcond * s[0]) inv[i] = 1.0 / s[i];
  }
  return -(svd.matrixV() * inv.asDiagonal() * svd.matrixU().transpose() * qtr);
}

class JacobianPinv : public Solver {
 public:
  explicit JacobianPinv(Options options) : options_(options) {}

  SolverSummary Solve(Problem& problem) override {
    const auto start = std::chrono::steady_clock::now();
    SolverSummary summary;
    summary.solver = "jacobian_pinv";
    const auto& free = problem.free_parameters();
    const Eigen::VectorXd lower = problem.LowerBounds(), upper = problem.UpperBounds();
    Eigen::VectorXd x = problem.FreeValues();
    double cost = 0.0;
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
    summary.stop_reason = "iteration limit reached";
    for (int it = 0; it <= options_.max_iterations; ++it) {
      if (!problem.Evaluate(&cost, &r, &J)) {
        summary.stop_reason = "a residual could not be evaluated";
        break;
      }
      ++summary.evaluations;
      if (it == 0) summary.initial_cost = cost;
      summary.final_cost = cost;
      if (it == options_.max_iterations || problem.num_free() == 0) break;
      Eigen::VectorXd dx = PseudoInverseStep(J, r, options_.rcond);
      double clip = 1.0, largest = 0.0;
      for (int i = 0; i < dx.size(); ++i) {
        const double limit = free[i].unit == "rad" ? options_.max_step_rad : options_.max_step_mm;
        clip = std::min(clip, limit / std::max(std::abs(dx[i]), 1e-300));
        largest = std::max(largest, std::abs(dx[i]));
      }
      x = (x + dx * clip).cwiseMax(lower).cwiseMin(upper);
      problem.SetFreeValues(x);
      summary.iterations = it + 1;
      if (largest * clip < options_.step_tolerance) {
        problem.Evaluate(&summary.final_cost, nullptr, nullptr);
        summary.converged = true;
        summary.stop_reason = "largest step below step_tolerance";
        break;
      }
    }
    summary.time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  }

 private:
  Options options_;
};

std::unique_ptr<Solver> Create(const ConfigNode& config) {
  config.ExpectKeys(
      {"type", "max_iterations", "max_step_mm", "max_step_rad", "step_tolerance", "rcond"});
  Options o;
  o.max_iterations = config.GetIntIn("max_iterations", o.max_iterations, 1, 1000000,
                                     "Allow at least one iteration; 100 is the default");
  o.max_step_mm = config.GetDoubleIn("max_step_mm", o.max_step_mm, 1e-12, 1e9,
                                     "The largest change of a length per iteration, above 0");
  o.max_step_rad = config.GetDoubleIn("max_step_rad", o.max_step_rad, 1e-12, 1e3,
                                      "The largest change of an angle per iteration, above 0");
  o.step_tolerance = config.GetDoubleIn("step_tolerance", o.step_tolerance, 0, 1,
                                        "A step in mm or rad below which the fit stops: 1e-10");
  o.rcond = config.GetDoubleIn("rcond", o.rcond, 0, 0.5,
                               "A relative singular value below which a direction is dropped: "
                               "1e-12");
  return std::make_unique<JacobianPinv>(o);
}

}  // namespace
}  // namespace cellmetry::jacobian_pinv

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "jacobian_pinv";
  info.description = "Gauss-Newton with an SVD pseudo-inverse (Huczala 2020, eq. 13)";
  info.options = {
      {"max_iterations", "", "100", "iteration limit"},
      {"max_step_mm", "mm", "100", "largest change of a length per iteration"},
      {"max_step_rad", "rad", "0.5", "largest change of an angle per iteration"},
      {"step_tolerance", "mm|rad", "1e-10", "stop when every step is below"},
      {"rcond", "", "1e-12", "singular values below rcond * largest are dropped"},
  };
  registry->AddSolver(info, &cellmetry::jacobian_pinv::Create);
}
