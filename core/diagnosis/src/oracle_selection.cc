// The oracle's Bayes choice among the candidates (oracle_selection.h).
#include "cellmetry/diagnosis/oracle_selection.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/model/effect_context.h"
#include "diagnosis_linear.h"
#include "oracle_draws.h"

namespace cellmetry {
namespace {

bool NamesExpected(const CandidateEffect& c, const std::string& expect) {
  return c.effect.name.rfind(expect, 0) == 0 || (!c.group.empty() && c.group == expect);
}

// Exact aliases of a right candidate are right: the finder names them together.
void MarkAliasesRight(double alias_correlation, std::vector<OracleChoice>* choices) {
  std::vector<size_t> named;
  for (size_t i = 0; i < choices->size(); ++i) {
    if ((*choices)[i].right) named.push_back(i);
  }
  for (auto& choice : *choices) {
    for (size_t i : named) {
      if (CanonicalCorrelation(choice.U, (*choices)[i].U) >= alias_correlation) {
        choice.right = true;
      }
    }
  }
}

// The testable candidates with their bases, as the finder's first round has them.
std::vector<OracleChoice> TestableChoices(const WorkcellProblem& spec, const Recording& recording,
                                          const std::vector<CandidateEffect>& candidates,
                                          const WorkcellEstimate& estimate,
                                          const std::string& expect,
                                          const DiagnosisOptions& options,
                                          Eigen::VectorXd* mismatch) {
  const NoiseModel noise = BuildNoiseModel(recording, spec.noise);
  WorkcellProblem all = spec;
  std::vector<WorkcellEffect> effects;
  for (const auto& c : candidates) {
    all.effects.push_back(c.effect);
    effects.push_back(c.effect);
  }
  const WorkcellData data = PrepareWorkcellData(all, recording);
  const CandidateLinearization base =
      LinearizeWithCandidate(spec, recording, data, noise, estimate, false);
  const std::vector<Eigen::MatrixXd> columns =
      CandidateColumns(spec, effects, recording, data, noise, estimate, base.r.size());
  const Eigen::MatrixXd Q = OrthonormalBasis(base.J_model);
  *mismatch = ProjectOut(Q, base.r);
  std::vector<OracleChoice> choices;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const CandidateEffect& c = candidates[i];
    if (!MissingFacts(c.effect.effect->needs(), data.facts).empty()) continue;
    const Eigen::MatrixXd P = ProjectOut(Q, columns[i]);
    const double total = columns[i].norm();
    if (total == 0.0 || P.norm() / total < options.min_unabsorbed_share) continue;
    OracleChoice choice{UnabsorbedBasis(columns[i], P), NamesExpected(c, expect)};
    if (choice.U.cols() > 0) choices.push_back(std::move(choice));
  }
  MarkAliasesRight(options.alias_correlation, &choices);
  return choices;
}

// The candidates' bases side by side, G = [U_1 ... U_C], and what the draws need of them: each
// one's first column, G^T d, and a map of standard normals to z = G^T e ~ N(0, G^T G) (from
// G^T G = V L V^T: V sqrt(L); the bases may overlap, so G^T G is not the identity).
struct StackedBases {
  std::vector<Eigen::Index> first;
  Eigen::VectorXd mean;
  Eigen::MatrixXd draw_map;
};

StackedBases Stack(const std::vector<OracleChoice>& choices, const Eigen::VectorXd& d) {
  StackedBases out;
  Eigen::Index K = 0;
  for (const auto& c : choices) {
    out.first.push_back(K);
    K += c.U.cols();
  }
  Eigen::MatrixXd G(d.size(), K);
  for (size_t i = 0; i < choices.size(); ++i) {
    G.middleCols(out.first[i], choices[i].U.cols()) = choices[i].U;
  }
  out.mean = G.transpose() * d;
  out.draw_map = NormalDrawMap(G.transpose() * G);
  return out;
}

// log p(r | c) = offset_c + gain_c |U_c^T r|^2, each candidate's coefficients a priori as large
// as the mismatch, spread over its k_c columns (oracle_selection.h).
struct Evidence {
  std::vector<double> offset, gain;
};

Evidence EvidenceOf(const std::vector<OracleChoice>& choices, double mismatch_norm2) {
  Evidence out;
  for (const auto& c : choices) {
    const double k = static_cast<double>(c.U.cols());
    const double tau2 = mismatch_norm2 / k;
    out.offset.push_back(-0.5 * k * std::log1p(tau2));
    out.gain.push_back(0.5 * tau2 / (1.0 + tau2));
  }
  return out;
}

}  // namespace

void DrawBayesChoices(const std::vector<OracleChoice>& choices, const Eigen::VectorXd& d,
                      const OracleSelectionOptions& options, OracleSelection* out) {
  out->right_by_posterior.assign(options.posterior_bins, 0);
  out->wrong_by_posterior.assign(options.posterior_bins, 0);
  if (choices.empty()) return;
  const StackedBases stacked = Stack(choices, d);
  const Evidence evidence = EvidenceOf(choices, d.squaredNorm());
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd n(stacked.mean.size()), log_p(choices.size());
  for (int draw = 0; draw < options.draws; ++draw) {
    for (Eigen::Index j = 0; j < n.size(); ++j) n[j] = normal(rng);
    const Eigen::VectorXd z = stacked.mean + stacked.draw_map * n;
    for (size_t i = 0; i < choices.size(); ++i) {
      log_p[i] = evidence.offset[i] +
                 evidence.gain[i] * z.segment(stacked.first[i], choices[i].U.cols()).squaredNorm();
    }
    Eigen::Index top = 0;
    const double best = log_p.maxCoeff(&top);
    const double posterior = 1.0 / (log_p.array() - best).exp().sum();
    const int bin =
        std::min(options.posterior_bins - 1, static_cast<int>(posterior * options.posterior_bins));
    ++(choices[top].right ? out->right_by_posterior : out->wrong_by_posterior)[bin];
  }
}

int OracleSelection::draws() const {
  int n = 0;
  for (int v : right_by_posterior) n += v;
  for (int v : wrong_by_posterior) n += v;
  return n;
}

double OracleSelection::right_share() const {
  int right = 0;
  for (int v : right_by_posterior) right += v;
  const int n = draws();
  return n > 0 ? static_cast<double>(right) / n : 0.0;
}

OracleSelection DrawOracleSelections(const WorkcellProblem& spec, const Recording& noise_free,
                                     const SolverMaker& make_solver,
                                     const std::vector<CandidateEffect>& candidates,
                                     const std::string& expect, const DiagnosisOptions& options,
                                     const OracleSelectionOptions& oracle) {
  WorkcellProblem geometry = spec;
  geometry.folds = 0;
  geometry.compare_camera_models = false;
  geometry.outlier_test = OutlierTest::kOff;  // the mismatch is the signal, never an outlier
  const WorkcellResult fit = IdentifyWorkcell(geometry, noise_free, make_solver);
  Eigen::VectorXd d;
  const std::vector<OracleChoice> choices =
      TestableChoices(geometry, noise_free, candidates, fit.estimate, expect, options, &d);
  OracleSelection out;
  out.mismatch_norm = d.norm();
  out.testable = static_cast<int>(choices.size());
  for (const auto& c : choices) out.right_candidates += c.right;
  if (out.right_candidates == 0) {  // nothing to score: no draws
    out.right_by_posterior.assign(oracle.posterior_bins, 0);
    out.wrong_by_posterior.assign(oracle.posterior_bins, 0);
    return out;
  }
  DrawBayesChoices(choices, d, oracle, &out);
  return out;
}

}  // namespace cellmetry
