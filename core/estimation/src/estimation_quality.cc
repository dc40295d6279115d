// How much to trust an answer (estimation_quality.h): unidentifiable directions, covariance, weak
// and correlated parameters, all from the SVD of the column-scaled whitened Jacobian.
#include "cellmetry/estimation/estimation_quality.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

// SVD of J's columns `columns`, each scaled to unit norm (so mm and rad compare), through J's R
// factor (r_factor.h): J = Q R, so J[:, c] / norm = Q (R[:, c] / norm) has the singular values
// and right singular vectors of an n x n matrix, whatever the number of rows.
Eigen::BDCSVD<Eigen::MatrixXd> ScaledSvd(const Eigen::MatrixXd& R, const std::vector<int>& columns,
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

namespace {

// Of the degenerate directions (the right singular vectors of `svd` whose singular value is below
// `tolerance` times the largest), the convention column with the largest share of their space
// (at least `kShare`), and the unit direction of that space that moves it most; -1 where none.
int ConventionColumn(const Eigen::BDCSVD<Eigen::MatrixXd>& svd, double tolerance,
                     const std::vector<int>& active, const std::vector<bool>& convention,
                     Eigen::VectorXd* direction) {
  constexpr double kShare = 0.1;  // as a partner: held, it leaves the others determined
  const Eigen::VectorXd& s = svd.singularValues();
  Eigen::Index dimension = 0;
  while (dimension < s.size() && s[s.size() - 1 - dimension] < tolerance * s[0]) ++dimension;
  const Eigen::MatrixXd null = svd.matrixV().rightCols(dimension);
  int best = -1;
  double best_share = kShare;
  for (size_t k = 0; k < active.size(); ++k) {
    if (!convention[static_cast<size_t>(active[k])]) continue;
    const double share = null.row(static_cast<Eigen::Index>(k)).norm();
    if (share >= best_share) {
      best = static_cast<int>(k);
      best_share = share;
    }
  }
  if (best >= 0) *direction = null * null.row(best).transpose() / best_share;
  return best;
}

}  // namespace

std::vector<DegenerateColumn> FindDegenerateColumns(const Eigen::MatrixXd& R,
                                                    const Eigen::VectorXd& norms, double tolerance,
                                                    const std::vector<bool>& convention) {
  std::vector<DegenerateColumn> found;
  std::vector<int> active;
  const double largest = norms.size() > 0 ? norms.maxCoeff() : 0.0;
  for (int j = 0; j < norms.size(); ++j) {
    if (norms[j] <= 1e-12 * largest) {
      found.push_back({j, /*no_data=*/true, {}, {}, {}});
    } else {
      active.push_back(j);
    }
  }
  while (active.size() > 1) {
    const auto svd = ScaledSvd(R, active, norms);
    const Eigen::VectorXd& s = svd.singularValues();
    const Eigen::Index last = s.size() - 1;
    if (s[last] >= tolerance * s[0]) break;
    Eigen::VectorXd v = svd.matrixV().col(last);
    Eigen::Index worst = 0;
    const int by_convention =
        convention.empty() ? -1 : ConventionColumn(svd, tolerance, active, convention, &v);
    if (by_convention >= 0) {
      worst = by_convention;
    } else {
      v.cwiseAbs().maxCoeff(&worst);
    }
    DegenerateColumn column{active[worst], /*no_data=*/false, {}, {}, {}};
    // v is in scaled columns (J D^-1, D the column norms): a parameter moves v_k / norm_k.
    const double worst_move = v[worst] / norms[active[worst]];
    for (Eigen::Index k = 0; k < v.size(); ++k) {
      if (k == worst || std::abs(v[k]) <= 0.1) continue;
      column.partners.push_back(active[k]);
      column.partner_ratios.push_back(v[k] / norms[active[k]] / worst_move);
      column.partner_shares.push_back(std::abs(v[k]));
    }
    found.push_back(column);
    active.erase(active.begin() + worst);
  }
  return found;
}

double GaugePriorSigma(const Parameter& p) { return p.plausible ? *p.plausible / 2.0 : 0.0; }

HeldParameters HeldOf(const std::vector<UnidentifiableParameter>& found) {
  HeldParameters held;
  for (const auto& u : found) {
    if (u.prior_sigma > 0.0) {
      held.prior_sigma[u.name] = u.prior_sigma;
    } else {
      held.held.insert(u.name);
    }
  }
  return held;
}

namespace {

// The free parameter `column` of `problem` (FreeParameter order) as a Parameter.
const Parameter& FreeParameterOf(const Problem& problem, int column) {
  const FreeParameter& f = problem.free_parameters()[static_cast<size_t>(column)];
  return problem.block_parameters(f.block)[static_cast<size_t>(f.index)];
}

// The column of `degenerate` (its own or a partner's) to give a gauge prior: the one with a
// plausible size and the largest share of the direction; -1 where none has one, or where no
// measurement depends on the column at all.
int GaugePriorColumn(const Problem& problem, const DegenerateColumn& degenerate) {
  if (degenerate.no_data) return -1;  // it moves nothing: held, it decides nothing either
  if (GaugePriorSigma(FreeParameterOf(problem, degenerate.column)) > 0.0) {
    return degenerate.column;
  }
  int best = -1;
  double best_share = 0.0;
  for (size_t k = 0; k < degenerate.partners.size(); ++k) {
    const int c = degenerate.partners[k];
    if (GaugePriorSigma(FreeParameterOf(problem, c)) <= 0.0) continue;
    if (degenerate.partner_shares[k] > best_share) {
      best = c;
      best_share = degenerate.partner_shares[k];
    }
  }
  return best;
}

UnidentifiableParameter Describe(const Problem& problem, const DegenerateColumn& degenerate,
                                 int named) {
  const auto& free = problem.free_parameters();
  std::vector<int> members = {degenerate.column};
  std::vector<double> ratios = {1.0};
  members.insert(members.end(), degenerate.partners.begin(), degenerate.partners.end());
  ratios.insert(ratios.end(), degenerate.partner_ratios.begin(), degenerate.partner_ratios.end());
  double named_ratio = 1.0;
  for (size_t k = 0; k < members.size(); ++k) {
    if (members[k] == named) named_ratio = ratios[k];
  }
  std::string partners;
  std::vector<GaugePartner> moves_with;
  for (size_t k = 0; k < members.size(); ++k) {
    if (members[k] == named) continue;
    const std::string& name = free[static_cast<size_t>(members[k])].name;
    partners += (partners.empty() ? "" : ", ") + name;
    moves_with.push_back({name, ratios[k] / named_ratio});
  }
  UnidentifiableParameter u;
  u.name = free[static_cast<size_t>(named)].name;
  u.reason = degenerate.no_data ? "no measurement depends on it"
             : partners.empty() ? "the data cannot separate it"
                                : "moves together with " + partners;
  u.moves_with = std::move(moves_with);
  return u;
}

}  // namespace

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
  std::vector<bool> convention;
  for (int c = 0; c < problem.num_free(); ++c) {
    convention.push_back(!FreeParameterOf(problem, c).convention.empty());
  }
  if (std::none_of(convention.begin(), convention.end(), [](bool b) { return b; })) {
    convention.clear();
  }
  std::vector<UnidentifiableParameter> found;
  for (const DegenerateColumn& column :
       FindDegenerateColumns(at->r_factor, ColumnNorms(gram), tolerance, convention)) {
    // The directions after the first were found with the first's column taken out (held):
    // one that gets a prior instead ends the list, and the caller looks again.
    // A convention decides its direction itself: no prior on a partner instead.
    const bool by_convention = !FreeParameterOf(problem, column.column).convention.empty();
    const int prior_column = by_convention ? -1 : GaugePriorColumn(problem, column);
    if (prior_column >= 0) {
      UnidentifiableParameter u = Describe(problem, column, prior_column);
      u.prior_sigma = GaugePriorSigma(FreeParameterOf(problem, prior_column));
      found.push_back(u);
      break;
    }
    found.push_back(Describe(problem, column, column.column));
    found.back().convention = FreeParameterOf(problem, column.column).convention;
  }
  return found;
}

void HoldParameters(Problem* problem, const HeldParameters& held) {
  for (int b = 0; b < problem->num_blocks(); ++b) {
    const auto& params = problem->block_parameters(b);
    for (size_t i = 0; i < params.size(); ++i) {
      const std::string name = problem->block_name(b) + "." + params[i].name;
      if (held.held.count(name)) problem->SetFixed(b, static_cast<int>(i), true);
      const auto prior = held.prior_sigma.find(name);
      if (prior != held.prior_sigma.end()) {
        problem->SetPrior(b, static_cast<int>(i), 0.0, prior->second);
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

IdentifiedSolve SolveHoldingUnidentifiable(Problem* problem, double tolerance, HeldParameters held,
                                           const SolverMaker& make_solver, bool warm_start) {
  IdentifiedSolve out;
  if (!held.held.empty() || !held.prior_sigma.empty()) HoldParameters(problem, held);
  // Before the solve the verdict is all that is kept; at the answer, its linearization too. A
  // gauge prior changes the problem, so the directions are looked for again after one (a
  // direction has at most as many members as there are free parameters).
  auto hold_unidentifiable = [&](Linearization* at) {
    bool changed = false;
    for (int round = 0; round <= problem->num_free(); ++round) {
      const auto found = FindUnidentifiable(*problem, tolerance, at);
      if (found.empty()) break;
      for (const auto& f : found) {
        if (f.prior_sigma > 0.0) {
          held.prior_sigma[f.name] = f.prior_sigma;
        } else {
          held.held.insert(f.name);
        }
      }
      out.unidentifiable.insert(out.unidentifiable.end(), found.begin(), found.end());
      HoldParameters(problem, held);
      changed = true;
    }
    return changed;
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

namespace {

// The information each free parameter's prior adds to J^T J (1 / sigma^2 on its diagonal, in
// FreeParameter order; zero where it has none). A prior row touches its one column only.
Eigen::VectorXd PriorInformation(const Problem& problem) {
  Eigen::VectorXd information = Eigen::VectorXd::Zero(problem.num_free());
  const auto& free = problem.free_parameters();
  for (size_t i = 0; i < free.size(); ++i) {
    const Parameter& p = problem.block_parameters(free[i].block)[free[i].index];
    if (p.prior_sigma && *p.prior_sigma > 0.0) {
      information[static_cast<Eigen::Index>(i)] = 1.0 / (*p.prior_sigma * *p.prior_sigma);
    }
  }
  return information;
}

// The chi-square over measurement rows only, and their count: priors are not measurements of
// the noise.
double MeasurementChiSquare(const Problem& problem, const Eigen::VectorXd& r, int* num_rows) {
  double chi2 = 0.0;
  *num_rows = 0;
  const auto& infos = problem.residual_infos();
  const auto& rows = problem.residual_rows();
  for (size_t b = 0; b < infos.size(); ++b) {
    if (infos[b].kind == ResidualInfo::Kind::kPrior) continue;
    const int end = b + 1 < rows.size() ? rows[b + 1] : static_cast<int>(r.size());
    for (int i = rows[b]; i < end; ++i) {
      chi2 += r[i] * r[i];
      ++*num_rows;
    }
  }
  return chi2;
}

// The covariance when the chi-square scale says the measurements' noise is larger than stated:
// a prior is a stated input, not a measurement, and keeps its sigma, so the information is the
// data's divided by the scale plus the priors' (a gauge the data cannot see keeps its prior).
// Empty where the scaled information is not positive definite.
std::optional<Eigen::MatrixXd> CovarianceKeepingPriorSigmas(
    const Eigen::MatrixXd& R, const Eigen::VectorXd& inv_norms,
    const Eigen::VectorXd& prior_information, double scale) {
  const Eigen::MatrixXd scaled_R = R * inv_norms.asDiagonal();
  const Eigen::VectorXd scaled_prior = prior_information.cwiseProduct(inv_norms.cwiseAbs2());
  Eigen::MatrixXd information = scaled_R.transpose() * scaled_R;
  information.diagonal() -= scaled_prior;
  information /= scale;
  information.diagonal() += scaled_prior;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(information);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
  const Eigen::MatrixXd scaled_inverse =
      ldlt.solve(Eigen::MatrixXd::Identity(information.rows(), information.cols()));
  return inv_norms.asDiagonal() * scaled_inverse * inv_norms.asDiagonal();
}

// Sigma from the covariance's diagonal, and the correlation (the identity where a sigma is 0).
void FillSigmaAndCorrelation(Uncertainty* u) {
  const int n = static_cast<int>(u->covariance.rows());
  u->sigma = u->covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double d = u->sigma[i] * u->sigma[j];
      u->correlation(i, j) = d > 0 ? u->covariance(i, j) / d : (i == j ? 1.0 : 0.0);
    }
  }
}

}  // namespace

Uncertainty ComputeUncertainty(Problem& problem) {
  return ComputeUncertainty(problem, Linearize(problem));
}

Uncertainty ComputeUncertainty(const Problem& problem, const Linearization& at) {
  if (!at.valid) {
    throw InputError({},
                     "the model cannot be evaluated at the fitted values (a cost function "
                     "failed: a pose out of reach or a non-finite value)",
                     "Check the recording for non-finite or far-off values and the start values");
  }
  Uncertainty u;
  const int n = problem.num_free();
  for (const auto& p : problem.free_parameters()) u.names.push_back(p.name);
  int measurement_rows = 0;
  u.chi2 = MeasurementChiSquare(problem, at.residuals, &measurement_rows);
  u.dof = measurement_rows - n;
  u.reduced_chi2 = u.dof > 0 ? u.chi2 / u.dof : 0.0;
  u.scale = std::max(1.0, u.reduced_chi2);
  u.covariance = Eigen::MatrixXd::Zero(n, n);
  u.inverse_information = u.covariance;
  u.sigma = Eigen::VectorXd::Zero(n);
  u.variance_inflation = Eigen::VectorXd::Ones(n);
  u.correlation = Eigen::MatrixXd::Identity(n, n);
  if (n == 0) return u;

  const SparseJacobian& gram = GramOf(at);
  const Eigen::VectorXd norms = ColumnNorms(gram).cwiseMax(1e-300);
  std::vector<int> every(n);
  for (int j = 0; j < n; ++j) every[j] = j;
  Eigen::MatrixXd factored;  // J's R factor where `at` has none yet
  const Eigen::MatrixXd& R = at.r_factor.size() > 0 ? at.r_factor : (factored = RFactor(gram));
  const auto svd = ScaledSvd(R, every, norms);
  const Eigen::VectorXd& s = svd.singularValues();
  u.condition_number = s[s.size() - 1] > 0 ? s[0] / s[s.size() - 1] : INFINITY;
  Eigen::VectorXd inv_s2 = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] > 1e-14 * s[0]) inv_s2[i] = 1.0 / (s[i] * s[i]);
  }
  const Eigen::MatrixXd& V = svd.matrixV();
  const Eigen::MatrixXd scaled_cov = V * inv_s2.asDiagonal() * V.transpose();
  u.variance_inflation = scaled_cov.diagonal();  // columns have unit norm
  const Eigen::VectorXd inv_norms = norms.cwiseInverse();
  u.inverse_information = inv_norms.asDiagonal() * scaled_cov * inv_norms.asDiagonal();
  u.covariance = u.inverse_information * u.scale;
  const Eigen::VectorXd prior_information = PriorInformation(problem);
  if (u.scale > 1.0 && prior_information.any()) {
    if (auto covariance = CovarianceKeepingPriorSigmas(R, inv_norms, prior_information, u.scale)) {
      u.covariance = std::move(*covariance);
    }
  }
  FillSigmaAndCorrelation(&u);
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
