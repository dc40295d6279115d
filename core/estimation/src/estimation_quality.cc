// How much to trust an answer (estimation_quality.h): unidentifiable directions, covariance, weak
// and correlated parameters, all from the SVD of the column-scaled whitened Jacobian.
#include "cellmetry/estimation/estimation_quality.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

// SVD of J's columns `columns`, each scaled to unit norm (so mm and rad compare), through J's R
// factor (r_factor.h): J = Q R, so J[:, c] / norm = Q (R[:, c] / norm) has the singular values
// and right singular vectors of an n x n matrix, whatever the number of rows.
Eigen::BDCSVD<Eigen::MatrixXd> ScaledSvd(const Eigen::MatrixXd& R,
                                            const std::vector<int>& columns,
                                            const Eigen::VectorXd& norms) {
  Eigen::MatrixXd scaled(R.rows(), static_cast<Eigen::Index>(columns.size()));
  for (size_t k = 0; k < columns.size(); ++k) {
    scaled.col(static_cast<Eigen::Index>(k)) = R.col(columns[k]) / norms[columns[k]];
  }
  // Divide and conquer: 5x quicker than one-sided Jacobi at 138 columns, as accurate here
  // (sigma to 1e-6 of the dense Jacobi path on the VSB jobs: test_r_factor).
  return Eigen::BDCSVD<Eigen::MatrixXd>(scaled, Eigen::ComputeFullV);
}

}  // namespace

std::vector<DegenerateColumn> FindDegenerateColumns(const Eigen::MatrixXd& R,
                                                    const Eigen::VectorXd& norms,
                                                    double tolerance) {
  std::vector<DegenerateColumn> found;
  std::vector<int> active;
  const double largest = norms.size() > 0 ? norms.maxCoeff() : 0.0;
  for (int j = 0; j < norms.size(); ++j) {
    if (norms[j] <= 1e-12 * largest) {
      found.push_back({j, /*no_data=*/true, {}, {}});
    } else {
      active.push_back(j);
    }
  }
  while (active.size() > 1) {
    const auto svd = ScaledSvd(R, active, norms);
    const Eigen::VectorXd s = svd.singularValues();
    const Eigen::Index last = s.size() - 1;
    if (s[last] >= tolerance * s[0]) break;
    const Eigen::VectorXd v = svd.matrixV().col(last);
    Eigen::Index worst = 0;
    v.cwiseAbs().maxCoeff(&worst);
    DegenerateColumn column{active[worst], /*no_data=*/false, {}, {}};
    // v is in scaled columns (J D^-1, D the column norms): a parameter moves v_k / norm_k.
    const double worst_move = v[worst] / norms[active[worst]];
    for (Eigen::Index k = 0; k < v.size(); ++k) {
      if (k == worst || std::abs(v[k]) <= 0.1) continue;
      column.partners.push_back(active[k]);
      column.partner_ratios.push_back(v[k] / norms[active[k]] / worst_move);
    }
    found.push_back(column);
    active.erase(active.begin() + worst);
  }
  return found;
}

std::vector<UnidentifiableParameter> FindUnidentifiable(Problem& problem, double tolerance,
                                                        Linearization* at) {
  Linearization local;
  if (at == nullptr) at = &local;
  *at = Linearization{};
  if (problem.num_free() == 0) return {};
  // The verdict reads J only through J^T J: without a caller for J, its Gram rows alone.
  const bool gram_only = at == &local && problem.HasGramRows();
  at->valid = problem.EvaluateSparse(at == &local ? nullptr : &at->residuals,
                                     gram_only ? nullptr : &at->jacobian, &at->gram);
  if (!at->valid) return {};
  const SparseJacobian& gram = GramOf(*at);
  at->r_factor = RFactor(gram);
  const auto& free = problem.free_parameters();
  std::vector<UnidentifiableParameter> found;
  for (const DegenerateColumn& column :
       FindDegenerateColumns(at->r_factor, ColumnNorms(gram), tolerance)) {
    std::string partners;
    std::vector<GaugePartner> moves_with;
    for (size_t k = 0; k < column.partners.size(); ++k) {
      const std::string& name = free[column.partners[k]].name;
      partners += (partners.empty() ? "" : ", ") + name;
      moves_with.push_back({name, column.partner_ratios[k]});
    }
    found.push_back({free[column.column].name,
                     column.no_data        ? "no measurement depends on it"
                     : partners.empty()    ? "the data cannot separate it"
                                           : "moves together with " + partners,
                     moves_with});
  }
  return found;
}

void HoldParameters(Problem* problem, const std::set<std::string>& names) {
  for (int b = 0; b < problem->num_blocks(); ++b) {
    const auto& params = problem->block_parameters(b);
    for (size_t i = 0; i < params.size(); ++i) {
      if (names.count(problem->block_name(b) + "." + params[i].name)) {
        problem->SetFixed(b, static_cast<int>(i), true);
      }
    }
  }
  problem->Build();
}

// A solve that ended on a non-finite parameter or cost has no answer: an error where it ends,
// never a result with NaN in it (exit 0) or a crash further on.
void CheckSolveEnded(const Problem& problem, const SolverSummary& summary) {
  std::string what;
  const Eigen::VectorXd x = problem.FreeValues();
  for (Eigen::Index i = 0; i < x.size() && what.empty(); ++i) {
    if (!std::isfinite(x[i])) what = problem.free_parameters()[i].name + " is not a number";
  }
  if (what.empty() && !std::isfinite(summary.final_cost)) what = "its cost is not finite";
  if (what.empty()) return;
  throw InputError({}, "the fit diverged (" + summary.solver + "): " + what,
                   "Check the start values, the recording for gross outliers, and the solver's "
                   "settings; nothing was written");
}

IdentifiedSolve SolveHoldingUnidentifiable(Problem* problem, double tolerance,
                                           std::set<std::string> held,
                                           const SolverMaker& make_solver, bool warm_start) {
  IdentifiedSolve out;
  if (!held.empty()) HoldParameters(problem, held);
  // Before the solve the verdict is all that is kept; at the answer, its linearization too.
  auto hold_unidentifiable = [&](Linearization* at) {
    const auto found = FindUnidentifiable(*problem, tolerance, at);
    for (const auto& f : found) held.insert(f.name);
    out.unidentifiable.insert(out.unidentifiable.end(), found.begin(), found.end());
    if (!found.empty()) HoldParameters(problem, held);
    return !found.empty();
  };
  if (!warm_start) hold_unidentifiable(nullptr);
  out.summary = make_solver()->Solve(*problem);
  CheckSolveEnded(*problem, out.summary);
  if (hold_unidentifiable(&out.at_answer)) {
    out.at_answer = Linearization{};  // made before the parameters it found were held
    out.summary = make_solver()->Solve(*problem);
    CheckSolveEnded(*problem, out.summary);
  }
  return out;
}

Uncertainty ComputeUncertainty(Problem& problem) {
  return ComputeUncertainty(problem, Linearize(problem));
}

Uncertainty ComputeUncertainty(const Problem& problem, const Linearization& at) {
  if (!at.valid) {
    throw InputError({}, "the model cannot be evaluated at the fitted values (a cost function "
                         "failed: a pose out of reach or a non-finite value)",
                     "Check the recording for non-finite or far-off values and the start values");
  }
  Uncertainty u;
  const Eigen::VectorXd& r = at.residuals;
  const int n = problem.num_free();
  for (const auto& p : problem.free_parameters()) u.names.push_back(p.name);
  // chi-square over measurement rows only: priors are not measurements of the noise.
  int measurement_rows = 0;
  const auto& infos = problem.residual_infos();
  const auto& rows = problem.residual_rows();
  for (size_t b = 0; b < infos.size(); ++b) {
    if (infos[b].kind == ResidualInfo::Kind::kPrior) continue;
    const int end = b + 1 < rows.size() ? rows[b + 1] : static_cast<int>(r.size());
    for (int i = rows[b]; i < end; ++i) {
      u.chi2 += r[i] * r[i];
      ++measurement_rows;
    }
  }
  u.dof = measurement_rows - n;
  u.reduced_chi2 = u.dof > 0 ? u.chi2 / u.dof : 0.0;
  u.scale = std::max(1.0, u.reduced_chi2);
  u.covariance = Eigen::MatrixXd::Zero(n, n);
  u.sigma = Eigen::VectorXd::Zero(n);
  u.variance_inflation = Eigen::VectorXd::Ones(n);
  u.correlation = Eigen::MatrixXd::Identity(n, n);
  if (n == 0) return u;

  const SparseJacobian& gram = GramOf(at);
  const Eigen::VectorXd norms = ColumnNorms(gram).cwiseMax(1e-300);
  std::vector<int> every(n);
  for (int j = 0; j < n; ++j) every[j] = j;
  const auto svd = ScaledSvd(at.r_factor.size() > 0 ? at.r_factor : RFactor(gram), every, norms);
  const Eigen::VectorXd s = svd.singularValues();
  u.condition_number = s[s.size() - 1] > 0 ? s[0] / s[s.size() - 1] : INFINITY;
  Eigen::VectorXd inv_s2 = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] > 1e-14 * s[0]) inv_s2[i] = 1.0 / (s[i] * s[i]);
  }
  const Eigen::MatrixXd& V = svd.matrixV();
  const Eigen::MatrixXd scaled_cov = V * inv_s2.asDiagonal() * V.transpose();
  u.variance_inflation = scaled_cov.diagonal();  // columns have unit norm
  const Eigen::VectorXd inv_norms = norms.cwiseInverse();
  u.covariance = inv_norms.asDiagonal() * scaled_cov * inv_norms.asDiagonal() * u.scale;
  u.sigma = u.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double d = u.sigma[i] * u.sigma[j];
      u.correlation(i, j) = d > 0 ? u.covariance(i, j) / d : (i == j ? 1.0 : 0.0);
    }
  }
  return u;
}

std::vector<WeakParameter> WeaklyIdentified(const Uncertainty& u, double vif_threshold) {
  std::vector<WeakParameter> weak;
  for (Eigen::Index i = 0; i < u.variance_inflation.size(); ++i) {
    if (u.variance_inflation[i] < vif_threshold) continue;
    WeakParameter w{u.names[i], u.variance_inflation[i], ""};
    for (Eigen::Index k = 0; k < u.correlation.cols(); ++k) {
      if (k == i || std::abs(u.correlation(i, k)) < 0.9) continue;
      char text[32];
      std::snprintf(text, sizeof(text), " (%.2f)", u.correlation(i, k));
      w.partners += (w.partners.empty() ? "" : ", ") + u.names[k] + text;
    }
    weak.push_back(w);
  }
  std::sort(weak.begin(), weak.end(), [](const WeakParameter& a, const WeakParameter& b) {
    return a.variance_inflation > b.variance_inflation;
  });
  return weak;
}

std::vector<CorrelatedPair> StrongCorrelations(const Uncertainty& u, double threshold) {
  std::vector<CorrelatedPair> pairs;
  const Eigen::Index n = u.correlation.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = i + 1; j < n; ++j) {
      if (std::abs(u.correlation(i, j)) >= threshold) {
        pairs.push_back({u.names[i], u.names[j], u.correlation(i, j)});
      }
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const CorrelatedPair& a, const CorrelatedPair& b) {
    return std::abs(a.correlation) > std::abs(b.correlation);
  });
  return pairs;
}

}  // namespace cellmetry
