// The physics finder (diagnosis.h): the geometric fit, then rounds that score every candidate
// effect, refit the best and accept it only if every test passes, then what remains unexplained.
#include "cellmetry/diagnosis/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>

#include <tbb/parallel_for.h>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/basics/error.h"
#include "cellmetry/basics/plausibility.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/basics/stage_clock.h"
#include "cellmetry/basics/statistics.h"
#include "cellmetry/cell/workcell.h"
#include "diagnosis_checkpoint.h"
#include "diagnosis_linear.h"
#include "diagnosis_regressors.h"

namespace cellmetry {
namespace {

// A model (geometry + accepted effects) fitted to the whole recording.
struct Fitted {
  WorkcellProblem spec;
  WorkcellResult result;
  FitSummary summary;
};

// The held-out figures of a fit's cross-validation.
void SummarizeHeldOut(Fitted* f) {
  f->summary.held_out_rms_mm = f->result.held_out.total.norm;
  f->summary.held_out_rms_se_mm = f->result.held_out.total_se_mm;
  double ss = 0.0;
  for (double fold : f->result.held_out.per_fold_normalized_rms) ss += fold * fold;
  const size_t n_folds = f->result.held_out.per_fold_normalized_rms.size();
  f->summary.held_out_sigma = n_folds ? std::sqrt(ss / n_folds) : 0.0;
}

Fitted Fit(const WorkcellProblem& spec, const Recording& recording, const SolverMaker& make_solver,
           int folds) {
  Fitted f;
  f.spec = spec;
  f.spec.folds = folds;
  f.spec.compare_camera_models = false;
  f.spec.leave_one_camera_out = false;
  f.result = IdentifyWorkcell(f.spec, recording, make_solver);
  ResidualRms tool;
  int rows = 0;  // scalar residuals
  for (const auto& row : f.result.residuals) {
    f.summary.chi2 += row.normalized.squaredNorm();
    rows += 3;
    if (row.kind == ResidualKind::kPosition && recording.IsCarried(row.target)) tool.Add(row.error);
  }
  tool.Finish();
  for (const WorkcellRobot& robot : spec.robots) {  // a level base's tilt over its sigma
    if (!robot.level_sigma_rad) continue;
    const Eigen::Vector3d z = f.result.estimate.T_world_base.at(robot.name).R.col(2);
    const double tilt = std::acos(std::min(1.0, std::abs(z.z())));
    f.summary.prior_chi2 += std::pow(tilt / *robot.level_sigma_rad, 2);
  }
  f.summary.rms_mm = tool.norm;
  f.summary.dof = rows - static_cast<double>(f.result.uncertainty.names.size());
  f.summary.p_value = ChiSquareSurvival(f.summary.chi2, f.summary.dof);
  SummarizeHeldOut(&f);
  return f;
}

// `refit` (a Fit without folds) with `folds`-fold cross-validation: what Fit with `folds` would
// return, without fitting again. IdentifyWorkcell's folds are the last step of the same fit,
// run at its answer with its noise model and held parameters; where the fit left outliers out,
// its folds ran on the recording without them, so it is fitted again in full.
Fitted WithHeldOut(const Fitted& refit, const Recording& recording, const SolverMaker& make_solver,
                   int folds) {
  if (!refit.result.outliers.empty()) return Fit(refit.spec, recording, make_solver, folds);
  Fitted f = refit;
  f.spec.folds = folds;
  const HeldParameters held = HeldOf(f.result.unidentifiable);
  StageClock clock;
  f.result.held_out = CrossValidate(f.spec, recording, PrepareWorkcellData(f.spec, recording),
                                    f.result.noise, f.result.estimate, held, make_solver);
  clock.Lap("cross_validation");
  for (StageTime& stage : f.result.stages) {  // the fit's own lap of its (empty) folds
    if (stage.stage == "cross_validation") stage = clock.stages().back();
  }
  SummarizeHeldOut(&f);
  return f;
}

WorkcellProblem With(const WorkcellProblem& spec, const CandidateEffect& candidate) {
  WorkcellProblem out = spec;
  out.effects.push_back(candidate.effect);
  return out;
}

// `spec` with `candidate` added, started from `current`'s answer (the candidate at zero, where
// it leaves the prediction as it is): the refit then needs only the steps the candidate takes.
WorkcellProblem WarmWith(const Fitted& current, const CandidateEffect& candidate) {
  WorkcellProblem out = With(current.spec, candidate);
  out.warm_start = current.result.estimate;
  return out;
}

// Fold-wise held-out gain of `after` over `before` (same folds) in normalized RMS (sigmas: a
// lateral error counts as much as a depth error of the same significance, where millimetres
// would let the noisy depth axis drown it), its mean and standard error.
std::pair<double, double> CvGain(const HeldOut& before, const HeldOut& after) {
  std::vector<double> gains;
  const auto& b = before.per_fold_normalized_rms;
  const auto& a = after.per_fold_normalized_rms;
  for (size_t f = 0; f < b.size() && f < a.size(); ++f) gains.push_back(b[f] - a[f]);
  if (gains.size() < 2) return {0.0, INFINITY};
  double mean = 0.0, ss = 0.0;
  for (double g : gains) mean += g;
  mean /= gains.size();
  for (double g : gains) ss += (g - mean) * (g - mean);
  return {mean, std::sqrt(ss / (gains.size() - 1) / gains.size())};
}

// The share of the held-out excess over the floor (mean square in sigmas minus 1) that a model
// removes against the one before. Where that excess is within chance of the floor (three
// standard errors of a mean square over the rows, sqrt(2 / rows)) there is nothing to share and
// the answer is 1: the other tests decide.
double ExplainedShare(const FitSummary& before, const FitSummary& after) {
  const double before_ms = before.held_out_sigma * before.held_out_sigma;
  const double after_ms = after.held_out_sigma * after.held_out_sigma;
  const double excess = before_ms - 1.0;
  if (excess <= 3.0 * std::sqrt(2.0 / std::max(1.0, before.dof))) return 1.0;
  return (before_ms - after_ms) / excess;
}

int CountPoses(const Recording& recording) {
  std::set<int> poses;
  for (const auto& s : recording.samples) poses.insert(s.pose);
  return static_cast<int>(poses.size());
}

// Checks the recording can support the tests at all.
void CheckInputs(const NoiseModel& noise, const Recording& recording,
                 const DiagnosisOptions& options, const std::string& origin,
                 std::string* noise_source) {
  const int poses = CountPoses(recording);
  if (poses < options.min_poses) {
    throw InputError({origin, 0, 0},
                     "too few samples for the tests: " + std::to_string(poses) +
                         " poses, the diagnosis needs at least " +
                         std::to_string(options.min_poses),
                     "Record more poses spread over the workspace");
  }
  std::set<std::string> sources;
  for (const auto& obs : recording.observations) {
    const TargetNoise& n = noise.at(obs.camera, obs.target);
    if (n.source == "unknown") {
      throw InputError({origin, 0, 0},
                       "no noise floor for " + obs.camera + "/" + obs.target +
                           ": no repeated captures and no sigma given",
                       "Capture some poses two or more times (samples sharing a pose id), or "
                       "give noise: {cameras: {" +
                           obs.camera +
                           ": {position_mm: [...]}}} in the "
                           "job");
    }
    sources.insert(n.source);
  }
  for (const auto& s : sources) *noise_source += (noise_source->empty() ? "" : "; ") + s;
}

double FloorRms(const Fitted& fit, const Recording& recording) {
  ResidualRms floor;
  for (const auto& row : fit.result.residuals) {
    if (row.kind != ResidualKind::kPosition || !recording.IsCarried(row.target)) continue;
    const Eigen::Vector3d sigma = row.error.cwiseQuotient(row.normalized);
    floor.Add(sigma.unaryExpr([](double v) { return std::isfinite(v) ? v : 0.0; }));
  }
  floor.Finish();
  return floor.norm;
}

// The largest tool displacement (mm) an effect with parameters `theta` predicts, to first order.
double PeakMm(const CandidateLinearization& lin, const Recording& recording,
              const Eigen::VectorXd& theta) {
  const Eigen::VectorXd whitened = lin.J_candidate * theta;
  std::map<int, Eigen::Vector3d> per_observation;
  for (Eigen::Index i = 0; i < whitened.size(); ++i) {
    const CandidateRow& info = lin.rows[i];
    if (info.kind != ResidualInfo::Kind::kPosition || info.label.observation < 0 ||
        !recording.IsCarried(info.label.target)) {
      continue;
    }
    auto& d =
        per_observation.try_emplace(info.label.observation, Eigen::Vector3d::Zero()).first->second;
    d[lin.row_axis[i]] = whitened[i] * info.sigma[lin.row_axis[i]];
  }
  double peak = 0.0;
  for (const auto& [obs, d] : per_observation) peak = std::max(peak, d.norm());
  return peak;
}

// The accepted effect's prediction on every carried-target position row beside the residual
// there before (`before`) and after (`after`) it was fitted (SignaturePoint).
std::vector<SignaturePoint> Signature(const CandidateLinearization& lin,
                                      const Eigen::VectorXd& theta, const WorkcellResult& before,
                                      const WorkcellResult& after) {
  std::map<int, Eigen::Vector3d> error_before, error_after;
  for (const auto& row : before.residuals) {
    if (row.kind == ResidualKind::kPosition) error_before[row.observation] = row.error;
  }
  for (const auto& row : after.residuals) {
    if (row.kind == ResidualKind::kPosition) error_after[row.observation] = row.error;
  }
  const Eigen::VectorXd whitened = lin.J_candidate * theta;
  std::vector<SignaturePoint> points;
  for (Eigen::Index i = 0; i < whitened.size(); ++i) {
    const CandidateRow& info = lin.rows[i];
    if (info.kind != ResidualInfo::Kind::kPosition || info.label.observation < 0) continue;
    const int axis = lin.row_axis[i];
    const double predicted = whitened[i] * info.sigma[axis];
    const auto b = error_before.find(info.label.observation);
    const auto a = error_after.find(info.label.observation);
    if (std::abs(predicted) < 1e-9 || b == error_before.end() || a == error_after.end()) continue;
    points.push_back({info.label.camera, axis, predicted, b->second[axis], a->second[axis]});
  }
  return points;
}

// The candidates (other families) whose unabsorbed signatures correlate with `chosen`'s by at
// least `threshold`, strongest first, as indices into `candidates`.
std::vector<std::pair<size_t, double>> LookAlikes(
    const std::vector<Eigen::MatrixXd>& unabsorbed_bases,
    const std::vector<const CandidateEffect*>& candidates, size_t chosen, double threshold) {
  std::vector<std::pair<size_t, double>> out;
  for (size_t c = 0; c < candidates.size(); ++c) {
    if (Overlap(*candidates[c], *candidates[chosen])) continue;
    const double correlation = CanonicalCorrelation(unabsorbed_bases[chosen], unabsorbed_bases[c]);
    if (correlation >= threshold) out.push_back({c, correlation});
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a.second > b.second; });
  return out;
}

// The first value unusual for its physics (JudgePlausibility; below zero without a margin: a
// refit worth accepting is well away from zero, so its sign is its own), in words; "" when all
// are ordinary.
std::string Unusual(const std::vector<Parameter>& parameters, const std::vector<double>& values) {
  const std::vector<PlausibilityFinding> found = JudgePlausibility(parameters, values);
  return found.empty() ? "" : PlausibilityText(parameters, values, found.front());
}

std::vector<int> RowPoses(const CandidateLinearization& lin) {
  std::vector<int> poses;
  for (const auto& row : lin.rows) poses.push_back(row.label.pose);
  return poses;
}

// What the bootstrap says of the chosen candidate (CandidateFinding::bootstrap_*).
struct BootstrapVerdict {
  double share = 0.0;        // resamples that included one of its `own` groups
  std::string rival;         // the label of the other group included most often ("": none was)
  std::string rival_effect;  // that group's member included most often, by name
};

// The share of bootstrap resamples that included a candidate of one of `own` groups (the chosen
// one's and its aliases', CandidateEffect::group_name), and the other group included most often.
BootstrapVerdict GroupInclusion(const std::vector<std::vector<int>>& inclusions,
                                const std::vector<const CandidateEffect*>& candidates,
                                const std::set<std::string>& own) {
  int resamples_own = 0;
  std::map<std::string, int> resamples_including;
  std::map<int, int> resamples_including_candidate;
  for (const auto& included : inclusions) {
    std::set<std::string> groups;
    for (int c : included) {
      groups.insert(candidates[c]->group_name());
      ++resamples_including_candidate[c];
    }
    bool any_own = false;
    for (const auto& g : groups) {
      ++resamples_including[g];
      any_own |= own.count(g) > 0;
    }
    resamples_own += any_own;
  }
  BootstrapVerdict verdict;
  std::string rival_group;
  int rival_count = 0;
  for (const auto& [group, count] : resamples_including) {
    if (!own.count(group) && count > rival_count) rival_count = count, rival_group = group;
  }
  int member_count = 0;
  for (const auto& [c, count] : resamples_including_candidate) {
    const CandidateEffect& candidate = *candidates[c];
    if (candidate.group_name() != rival_group || count <= member_count) continue;
    member_count = count;
    verdict.rival = candidate.group_label.empty() ? candidate.label : candidate.group_label;
    verdict.rival_effect = candidate.effect.name;
  }
  verdict.share = resamples_own / double(std::max<size_t>(1, inclusions.size()));
  return verdict;
}

// One round's candidates, scored on the current model's linearization.
struct ScoredRound {
  DiagnosisRound round;
  CandidateLinearization base;                    // residuals over sqrt(dispersion)
  std::vector<const CandidateEffect*> testable;   // parallel to round.candidates
  std::vector<Eigen::MatrixXd> signatures;        // their Jacobian columns
  std::vector<Eigen::MatrixXd> unabsorbed_bases;  // orthonormal, outside the model's span
  std::vector<Eigen::MatrixXd> unabsorbed;        // the signatures outside it, by parameter
};

// The round's refits stronger than `chosen` whose size rules them out (AcceptedEffect::
// stronger_implausible), strongest first.
std::vector<std::string> StrongerImplausible(const DiagnosisRound& round,
                                             const CandidateFinding& chosen) {
  std::vector<const CandidateFinding*> stronger;
  const double strength = Strength(chosen.likelihood_ratio, chosen.dof);
  for (const auto& f : round.candidates) {
    if (f.refitted && !f.implausible.empty() && Strength(f.likelihood_ratio, f.dof) > strength) {
      stronger.push_back(&f);
    }
  }
  std::sort(stronger.begin(), stronger.end(), [](const auto* a, const auto* b) {
    return Strength(a->likelihood_ratio, a->dof) > Strength(b->likelihood_ratio, b->dof);
  });
  std::vector<std::string> out;
  for (const auto* f : stronger) out.push_back(f->label + ": " + f->implausible);
  return out;
}

// The canonical correlation of the round's chosen candidate's unabsorbed signature with that of
// every other testable candidate at its site (AcceptedEffect::site_correlations).
std::map<std::string, double> SiteCorrelations(const ScoredRound& s, int chosen) {
  std::map<std::string, double> out;
  const std::string& site = s.testable[chosen]->site;
  if (site.empty()) return out;
  for (size_t c = 0; c < s.testable.size(); ++c) {
    if (static_cast<int>(c) == chosen || s.testable[c]->site != site) continue;
    out[s.testable[c]->effect.name] =
        CanonicalCorrelation(s.unabsorbed_bases[chosen], s.unabsorbed_bases[c]);
  }
  return out;
}

// The steps of one diagnosis, over the data every step shares.
class Diagnoser {
 public:
  Diagnoser(const Recording& recording, const SolverMaker& make_solver,
            const std::vector<CandidateEffect>& candidates, const DiagnosisOptions& options,
            const NoiseModel& noise, const WorkcellData& data)
      : recording_(recording), make_solver_(make_solver), candidates_(candidates),
        options_(options), noise_(noise), data_(data), n_poses_(CountPoses(recording)) {}

  // A candidate's finding from its score test; untestable (and why) where the recording lacks
  // its facts, it does not act (`silent`: its columns are zero), or the data could not tell it
  // at its plausible size (`detectable`, over the round's dispersion: below what a score test
  // at alpha needs) however little of it the geometry absorbs.
  CandidateFinding Finding(const CandidateEffect& c, const ScoreTest& test, bool silent,
                           double detectable) const {
    CandidateFinding f;
    f.name = c.effect.name;
    f.label = c.label;
    f.site = c.site;
    f.unabsorbed = test.unabsorbed;
    f.detectable = detectable;
    f.dof = test.dof;
    f.score = test.statistic;
    f.p_holm = test.p_value;
    const std::string missing = MissingFacts(c.effect.effect->needs(), data_.facts);
    const double needed = ChiSquareQuantile(1.0 - options_.alpha, 1.0);
    const bool too_weak = std::isnan(detectable)
                              ? test.unabsorbed < options_.min_unabsorbed_share
                              : test.unabsorbed < options_.min_unabsorbed || detectable < needed;
    if (!missing.empty() || silent || too_weak || test.dof == 0) {
      f.testable = false;
      const std::string absorbed = std::to_string(int(std::floor(100 * (1 - test.unabsorbed)))) +
                                   " % of its signature is absorbed by the geometry";
      char weak[160];
      std::snprintf(weak, sizeof weak,
                    "at its plausible size it would add %.2g to the score statistic, below the "
                    "%.3g a test at %g needs (%s)",
                    detectable, needed, options_.alpha, absorbed.c_str());
      f.untestable_because = !missing.empty() ? std::string("not in this recording or robot model")
                             : silent         ? "it does not act on these poses"
                             : std::isnan(detectable) || test.unabsorbed < options_.min_unabsorbed
                                 ? absorbed
                                 : std::string(weak);
      f.data_needed = !missing.empty() ? missing : c.data_hint;
    }
    return f;
  }

  // The rival the chosen candidate beats least clearly: RivalTestPAt against every testable
  // candidate outside the chosen one's own groups and aliases (`own`) that could be the cause;
  // the largest p and whose.
  void WorstRival(const ScoredRound& s, int best, const std::set<std::string>& own, unsigned seed,
                  CandidateFinding* chosen) const {
    std::vector<double> p(s.testable.size(), 0.0);
    tbb::parallel_for(size_t(0), s.testable.size(), [&](size_t j) {
      if (static_cast<int>(j) == best || own.count(s.testable[j]->group_name())) return;
      if (Overlap(*s.testable[j], *s.testable[best])) return;  // nested: one contains the other
      if (!CredibleCause(s, j)) return;
      p[j] = RivalTestPAt(options_.alpha, s.base.r, s.unabsorbed_bases[best], s.unabsorbed_bases[j],
                          options_.rival_draws, seed + static_cast<unsigned>(j));
    });
    const size_t worst = std::max_element(p.begin(), p.end()) - p.begin();
    chosen->rival_p = p[worst];
    if (p[worst] > 0) {
      chosen->rival = s.testable[worst]->label;
      chosen->rival_effect = s.testable[worst]->effect.name;
    }
  }

  // Whether testable candidate `j`, alone the cause of the round's mismatch, would have a sign
  // its physics can have (its linearized refit, UnabsorbedSize). A negative clearance, play or
  // compliance is no physics at all (Parameter::plausible_nonnegative), so no rival the chosen
  // one has to beat. A size beyond the plausible one is not enough to set a rival aside: that
  // bound says "typically", and something of the rival's shape may still be the cause (the
  // report names what shares it). The residuals are over sqrt(dispersion); the size is not.
  bool CredibleCause(const ScoredRound& s, size_t j) const {
    const Eigen::VectorXd size =
        std::sqrt(s.round.dispersion) * UnabsorbedSize(s.unabsorbed[j], s.base.r);
    const std::vector<Parameter>& parameters = s.testable[j]->effect.effect->parameters();
    for (Eigen::Index i = 0; i < size.size() && i < static_cast<Eigen::Index>(parameters.size());
         ++i) {
      if (PlausibilityOf(parameters[i], size[i]) == Plausibility::kBelowZero) return false;
    }
    return true;
  }

  // Linearizes the current model once, scores every candidate not `done`; untestable ones go
  // to `untestable` and join `done`.
  // `frames_only`: the frame candidates alone (CandidateEffect::frame), for TestFrame.
  ScoredRound Score(const Fitted& current, std::set<std::string>* done,
                    std::vector<CandidateFinding>* untestable, bool frames_only = false) const {
    ScoredRound s;
    s.base = LinearizeWithCandidate(current.spec, recording_, data_, noise_,
                                    current.result.estimate, false);
    // Quasi-likelihood (McCullagh & Nelder 1989, sec. 9.2): where the residuals scatter wider
    // than the floor, an effect is judged against the scatter the model leaves, not against the
    // floor; a real recording whose mismatch is 10x the floor's chi-square otherwise passes
    // every candidate that takes a sliver of it. At the floor the dispersion is 1.
    s.round.dispersion = std::max(1.0, current.summary.chi2 / std::max(1.0, current.summary.dof));
    // A prior (a robot standing level, a gauge's plausible size) is a stated input, not a
    // measurement: the dispersion does not widen it. Its rows are weighted up by what the
    // measurements' rows are weighted down, so that the division below leaves them as stated.
    const double up = std::sqrt(s.round.dispersion);
    for (size_t i = 0; i < s.base.rows.size(); ++i) {
      if (s.base.rows[i].kind != ResidualInfo::Kind::kPrior) continue;
      s.base.J_model.row(static_cast<Eigen::Index>(i)) *= up;
      s.base.r[static_cast<Eigen::Index>(i)] *= up;
    }
    s.base.r /= std::sqrt(s.round.dispersion);
    std::vector<const CandidateEffect*> open;
    std::vector<WorkcellEffect> effects;
    for (const auto& c : candidates_) {
      if (done->count(c.effect.name) || (frames_only && !c.frame)) continue;
      open.push_back(&c);
      effects.push_back(c.effect);
    }
    Progress::Note("linearizing the model with " + std::to_string(open.size()) +
                   (open.size() == 1 ? " candidate" : " candidates") + " at zero");
    std::vector<Eigen::MatrixXd> signatures = CandidateColumns(
        current.spec, effects, recording_, data_, noise_, current.result.estimate, s.base.r.size());
    const Eigen::MatrixXd Q = OrthonormalBasis(s.base.J_model);
    std::vector<ScoreTest> tests(open.size());
    std::vector<Eigen::MatrixXd> bases(open.size()), unabsorbed(open.size());
    tbb::parallel_for(size_t(0), open.size(), [&](size_t i) {
      unabsorbed[i] = ProjectOut(Q, signatures[i]);
      tests[i] = cellmetry::Score(s.base.r, signatures[i], unabsorbed[i]);
      bases[i] = OrthonormalBasis(unabsorbed[i]);
    });
    for (size_t i = 0; i < open.size(); ++i) {
      const double detectable =
          PlausibleNoncentrality(unabsorbed[i], open[i]->effect.effect->parameters()) /
          s.round.dispersion;
      CandidateFinding f = Finding(*open[i], tests[i], signatures[i].norm() == 0.0, detectable);
      if (!f.testable) {
        untestable->push_back(f);
        done->insert(open[i]->effect.name);
        continue;
      }
      s.round.candidates.push_back(f);
      s.testable.push_back(open[i]);
      s.signatures.push_back(std::move(signatures[i]));
      s.unabsorbed_bases.push_back(std::move(bases[i]));
      s.unabsorbed.push_back(std::move(unabsorbed[i]));
    }
    // Holm over the round's candidates, on the score tests.
    std::vector<double> p;
    for (const auto& f : s.round.candidates) p.push_back(f.p_holm);
    const std::vector<double> adjusted = HolmAdjusted(p);
    for (size_t i = 0; i < p.size(); ++i) s.round.candidates[i].p_holm = adjusted[i];
    return s;
  }

  // Refits the `options.refits` best-scoring candidates in full (nonlinear); returns the index
  // of the strongest refit and moves its fit to `best_fit`.
  int RefitBest(const Fitted& current, ScoredRound* s, Fitted* best_fit) const {
    auto& candidates = s->round.candidates;
    std::vector<size_t> order;  // frames wait for TestFrame: held-out error cannot judge them
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (!s->testable[i]->frame) order.push_back(i);
    }
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return Strength(candidates[a].score, candidates[a].dof) >
             Strength(candidates[b].score, candidates[b].dof);
    });
    // The refits side by side (each solve's own threads leave its serial parts to overlap).
    const size_t n = std::min<size_t>(order.size(), std::max(0, options_.refits));
    Progress progress("refitting the strongest candidates:", static_cast<int>(n));
    std::vector<Fitted> refits(n);
    std::mutex progress_mutex;
    tbb::parallel_for(size_t(0), n, [&](size_t k) {
      refits[k] = Fit(WarmWith(current, *s->testable[order[k]]), recording_, make_solver_, 0);
      const std::lock_guard<std::mutex> lock(progress_mutex);
      progress.Advance();
    });
    int best = -1;
    for (size_t k = 0; k < n; ++k) {
      CandidateFinding& f = candidates[order[k]];
      Fitted& refit = refits[k];
      f.refitted = true;
      f.likelihood_ratio =
          std::max(0.0, current.summary.chi2 - refit.summary.chi2) / s->round.dispersion;
      f.p_lr_holm = std::min(1.0, ChiSquareSurvival(f.likelihood_ratio, f.dof) *
                                      static_cast<double>(candidates.size()));
      // BIC's n: the poses, the experiment's independent units (cross-validation and the
      // bootstrap draw whole poses too); a pose's rows are not independent draws of a signature.
      f.delta_bic = f.dof * std::log(n_poses_) - f.likelihood_ratio;
      const CandidateEffect& c = *s->testable[order[k]];
      f.implausible =
          Unusual(c.effect.effect->parameters(), refit.result.estimate.effects.at(c.effect.name));
      // A plausible refit beats every implausible one; among equals the stronger wins.
      const auto& incumbent = candidates[std::max(best, 0)];
      const bool better = best < 0 || (f.implausible.empty() && !incumbent.implausible.empty()) ||
                          (f.implausible.empty() == incumbent.implausible.empty() &&
                           Strength(f.likelihood_ratio, f.dof) >
                               Strength(incumbent.likelihood_ratio, incumbent.dof));
      if (better) {
        best = static_cast<int>(order[k]);
        *best_fit = std::move(refit);
      }
    }
    return best;
  }

  // Cross-validation, aliases and bootstrap inclusion of the round's chosen candidate; sets its
  // verdict and returns its fit with held-out figures.
  Fitted TestChosen(const Fitted& current, ScoredRound* s, int best, const Fitted& best_fit,
                    int effects_left, unsigned seed) const {
    CandidateFinding& chosen = s->round.candidates[best];
    Progress::Note("cross-validating and bootstrapping " + chosen.label);
    Fitted with_cv = WithHeldOut(best_fit, recording_, make_solver_, options_.folds);
    const auto [gain, se] = CvGain(current.result.held_out, with_cv.result.held_out);
    chosen.cv_rms_mm = with_cv.summary.held_out_rms_mm;
    chosen.cv_gain = gain;
    chosen.cv_gain_se = se;
    // Aliases: candidates whose unabsorbed signatures these poses cannot tell from the chosen
    // one's at all (a gear ratio and a once-per-turn error over less than a turn). No estimator
    // can pick between them, so the bootstrap asks whether the finding is stable, not which of
    // its names wins, and the report names both.
    std::set<std::string> own = {s->testable[best]->group_name()};
    // One whose size rules it out names more of what shares its signature.
    const double look_alike = chosen.implausible.empty() ? 0.8 : 0.5;
    for (const auto& [c, correlation] :
         LookAlikes(s->unabsorbed_bases, s->testable, best, look_alike)) {
      chosen.look_alikes.push_back({s->testable[c]->label, correlation});
      if (correlation >= options_.alias_correlation) {
        own.insert(s->testable[c]->group_name());
        chosen.aliases.push_back(s->testable[c]->label);
        chosen.alias_names.push_back(s->testable[c]->effect.name);
      }
    }
    const std::vector<std::vector<int>> inclusions =
        BootstrapInclusions(s->base.r, s->base.J_model, s->signatures, RowPoses(s->base),
                            options_.bootstrap, std::log(n_poses_), effects_left, seed);
    const BootstrapVerdict bootstrap = GroupInclusion(inclusions, s->testable, own);
    chosen.bootstrap_share = bootstrap.share;
    chosen.bootstrap_rival = bootstrap.rival;
    chosen.bootstrap_rival_effect = bootstrap.rival_effect;
    chosen.explained_share = ExplainedShare(current.summary, with_cv.summary);
    if (!chosen.implausible.empty()) chosen.failed.push_back("size");
    if (!(chosen.p_lr_holm < options_.alpha)) chosen.failed.push_back("LR");
    if (!(chosen.delta_bic < 0)) chosen.failed.push_back("BIC");
    if (!(gain > se)) chosen.failed.push_back("CV");
    if (chosen.explained_share < options_.min_explained_share) chosen.failed.push_back("share");
    // Better held out over every row, worse on the positions alone: it trades the positions
    // for the rotations (sim B's depth quadratic did: 0.85 -> 0.97 mm), not the physics.
    if (with_cv.summary.held_out_rms_mm > 1.01 * current.summary.held_out_rms_mm) {
      chosen.failed.push_back("positions");
    }
    if (options_.selection_test == "rivals") {
      WorstRival(*s, best, own, seed, &chosen);
      if (!(chosen.rival_p < options_.alpha)) chosen.failed.push_back("rivals");
    } else if (chosen.bootstrap_share < options_.bootstrap_share) {
      chosen.failed.push_back("bootstrap");
    }
    chosen.accepted = chosen.failed.empty();
    return with_cv;
  }

  // The accepted effect in words, with its parameters and the most it moves the tool.
  AcceptedEffect Describe(const CandidateEffect& c, const CandidateFinding& chosen,
                          const Fitted& with_cv, const Fitted& current) const {
    AcceptedEffect a;
    a.name = c.effect.name;
    a.label = c.label;
    a.site = c.site;
    a.group = c.group;
    a.group_label = c.group_label;
    a.held_out_sigma_before = current.summary.held_out_sigma;
    a.held_out_sigma_after = with_cv.summary.held_out_sigma;
    const std::vector<double>& values = with_cv.result.estimate.effects.at(c.effect.name);
    a.description = c.effect.effect->Describe(values);
    a.aliases = chosen.aliases;
    a.alias_names = chosen.alias_names;
    a.look_alikes = chosen.look_alikes;
    for (const auto& s : with_cv.result.model_parameters) {
      if (s.name.rfind(c.effect.name + ".", 0) == 0) a.parameters.push_back(s);
    }
    const CandidateLinearization lin = LinearizeWithCandidate(
        With(current.spec, c), recording_, data_, noise_, current.result.estimate, true);
    const Eigen::Map<const Eigen::VectorXd> theta(values.data(), values.size());
    a.peak_mm = PeakMm(lin, recording_, theta);
    a.signature = Signature(lin, theta, current.result, with_cv.result);
    return a;
  }

  // The fit a finished round ended with, for a round read back from a checkpoint: RefitBest's
  // refit of `c` with TestChosen's folds, or (`frame`) TestFrame's fit.
  Fitted Refit(const Fitted& current, const CandidateEffect& c, bool frame) const {
    if (frame) return Fit(WarmWith(current, c), recording_, make_solver_, options_.folds);
    return WithHeldOut(Fit(WarmWith(current, c), recording_, make_solver_, 0), recording_,
                       make_solver_, options_.folds);
  }

  // The strongest frame candidate (CandidateEffect::frame) of a round scored at `current`, if
  // its score test passes, refitted and accepted where its likelihood-ratio test passes too and
  // its size is plausible. A frame is one question the job's statements pose (is the world tag
  // level?), asked once whatever the physics search found, so its tests are corrected for the
  // frames asked, not for every candidate of the round (Bonferroni). Held-out error does not
  // judge it: a frame moves no prediction. -1 when none was tried.
  int TestFrame(const Fitted& current, ScoredRound* s, Fitted* with_cv) const {
    auto& candidates = s->round.candidates;
    std::vector<int> frames;
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (s->testable[i]->frame) frames.push_back(static_cast<int>(i));
    }
    const double asked = static_cast<double>(frames.size());
    int best = -1;
    for (int i : frames) {
      const CandidateFinding& f = candidates[i];
      if (!(ChiSquareSurvival(f.score, f.dof) * asked < options_.alpha)) continue;
      if (best < 0 || f.score > candidates[best].score) best = i;
    }
    if (best < 0) return -1;
    CandidateFinding& f = candidates[best];
    const CandidateEffect& c = *s->testable[best];
    Progress::Note("testing " + c.label + ", a frame the job's statements determine");
    *with_cv = Fit(WarmWith(current, c), recording_, make_solver_, options_.folds);
    f.refitted = true;
    // The job's stated priors count too: a level statement is what determines a frame.
    f.likelihood_ratio =
        std::max(0.0, (current.summary.chi2 - with_cv->summary.chi2) / s->round.dispersion +
                          current.summary.prior_chi2 - with_cv->summary.prior_chi2);
    f.p_lr_holm = std::min(1.0, ChiSquareSurvival(f.likelihood_ratio, f.dof) * asked);
    f.implausible =
        Unusual(c.effect.effect->parameters(), with_cv->result.estimate.effects.at(c.effect.name));
    f.cv_rms_mm = with_cv->summary.held_out_rms_mm;
    if (!f.implausible.empty()) f.failed.push_back("size");
    if (!(f.p_lr_holm < options_.alpha)) f.failed.push_back("LR");
    f.accepted = f.failed.empty();
    return best;
  }

  // Where the current model's residuals follow the recorded regressors, strongest first.
  std::vector<RegressorFinding> Regressors(const Fitted& current,
                                           const std::vector<Regressor>& regressors) const {
    const CandidateLinearization lin = LinearizeWithCandidate(
        current.spec, recording_, data_, noise_, current.result.estimate, false);
    return CorrelateRegressors(lin, recording_, regressors);
  }

  // Structure the library did not explain: a regressor the residuals still follow (a more
  // powerful test than the omnibus chi-square against one concentrated cause), or a chi-square
  // above the floor; "" when the residuals look like noise.
  std::string Unexplained(const FitSummary& current,
                          const std::vector<RegressorFinding>& findings) const {
    if (!findings.empty() && findings.front().p_value < options_.alpha) {
      const auto& f = findings.front();
      return "structure remains along " + f.regressor + " (" + f.axis +
             " residuals, partial correlation " +
             std::to_string(f.partial_correlation).substr(0, 5) + ")";
    }
    if (!current.consistent_with_noise()) {
      return "the residuals exceed the floor but follow none of the recorded regressors";
    }
    return "";
  }

 private:
  const Recording& recording_;
  const SolverMaker& make_solver_;
  const std::vector<CandidateEffect>& candidates_;
  const DiagnosisOptions& options_;
  const NoiseModel& noise_;
  const WorkcellData& data_;
  const double n_poses_;
};

}  // namespace

bool Overlap(const CandidateEffect& a, const CandidateEffect& b) {
  if (a.family_name() == b.family_name()) return true;
  for (const std::string& atom : a.atoms) {
    if (std::find(b.atoms.begin(), b.atoms.end(), atom) != b.atoms.end()) return true;
  }
  return false;
}

namespace {

// The candidate named `name` (a resumed round's accepted effect).
const CandidateEffect& CandidateNamed(const std::vector<CandidateEffect>& candidates,
                                      const std::string& name) {
  for (const auto& c : candidates) {
    if (c.effect.name == name) return c;
  }
  throw std::runtime_error("diagnosis checkpoint: no candidate " + name);
}

// What a diagnosis carries from round to round.
struct RoundState {
  Fitted current;              // the model so far, fitted
  std::set<std::string> done;  // accepted or untestable
};

RoundRecord RecordOf(const DiagnosisRound& round, const DiagnosisResult& out,
                     const RoundState& state, bool accepted) {
  RoundRecord record;
  record.round = round;
  if (accepted) record.accepted = out.accepted.back();
  record.untestable = out.untestable;
  record.done.assign(state.done.begin(), state.done.end());
  return record;
}

// Round `index` as it finished before (`record`, from the log): into `out` and `state`, its
// accepted effect refitted into the model.
void ResumeRound(const Diagnoser& diagnoser, const RoundRecord& record, int index,
                 const std::vector<CandidateEffect>& candidates, RoundState* state,
                 DiagnosisResult* out) {
  Progress::Note("round " + std::to_string(index) + ": finished before, read back");
  out->untestable = record.untestable;
  state->done.insert(record.done.begin(), record.done.end());
  if (record.accepted) {
    const CandidateEffect& c = CandidateNamed(candidates, record.accepted->name);
    state->current = diagnoser.Refit(state->current, c, record.round.frames);
    out->accepted.push_back(*record.accepted);
  }
  out->rounds.push_back(record.round);
}

// Rounds of the physics (step 5), each accepting the strongest candidate that passes every test,
// until none does or `options.max_effects` are accepted. Returns the rounds run or read back,
// each a step of `progress`.
int RunPhysicsRounds(const Diagnoser& diagnoser, const std::vector<CandidateEffect>& candidates,
                     const DiagnosisOptions& options, RoundLog& log, RoundState* state,
                     Progress* progress, DiagnosisResult* out) {
  int steps = 0;
  // The rounds run whatever the omnibus chi-square says: one effect of SNR 6 among thousands of
  // residual rows moves it by 36 against a spread of sqrt(2 * rows), so it has little power;
  // the targeted tests have it. Rounds end when no candidate passes every test.
  while (static_cast<int>(out->accepted.size()) < options.max_effects) {
    const int index = static_cast<int>(out->rounds.size()) + 1;
    if (const std::optional<RoundRecord> finished = log.Finished(index)) {
      if (finished->round.frames) break;  // the frames' step came next: this loop ended before
      ResumeRound(diagnoser, *finished, index, candidates, state, out);
      progress->Resume(1);
      ++steps;
      if (!finished->accepted) break;
      continue;
    }
    progress->Begin("round " + std::to_string(index) + ", scoring " +
                    std::to_string(candidates.size() - state->done.size()) + " candidate effects");
    Fitted& current = state->current;
    ScoredRound scored = diagnoser.Score(current, &state->done, &out->untestable);
    if (scored.round.candidates.empty()) break;
    Fitted best_fit;
    const int best = diagnoser.RefitBest(current, &scored, &best_fit);
    if (best < 0) break;  // only frames left
    Fitted with_cv =
        diagnoser.TestChosen(current, &scored, best, best_fit,
                             options.max_effects - static_cast<int>(out->accepted.size()),
                             17u + static_cast<unsigned>(out->rounds.size()));
    const CandidateFinding& chosen = scored.round.candidates[best];
    const bool accepted = chosen.accepted;
    if (accepted) {
      const CandidateEffect& c = *scored.testable[best];
      scored.round.accepted = chosen.name;
      out->accepted.push_back(diagnoser.Describe(c, chosen, with_cv, current));
      out->accepted.back().site_correlations = SiteCorrelations(scored, best);
      out->accepted.back().stronger_implausible = StrongerImplausible(scored.round, chosen);
      for (const auto& other : candidates) {  // its nested variants would repeat its parameters
        if (Overlap(other, c)) state->done.insert(other.effect.name);
      }
      current = std::move(with_cv);
    }
    log.Keep(index, RecordOf(scored.round, *out, *state, accepted));
    out->rounds.push_back(std::move(scored.round));
    progress->Advance();
    ++steps;
    if (!accepted) break;
  }
  return steps;
}

// The frames the job's statements determine, after the physics (they move no prediction), one a
// round. Returns the rounds run or read back, each a step of `progress`.
int RunFrameRounds(const Diagnoser& diagnoser, const std::vector<CandidateEffect>& candidates,
                   RoundLog& log, RoundState* state, Progress* progress, DiagnosisResult* out) {
  int steps = 0;
  auto frame_open = [&] {
    return std::any_of(candidates.begin(), candidates.end(), [&](const CandidateEffect& c) {
      return c.frame && !state->done.count(c.effect.name);
    });
  };
  while (frame_open()) {
    const int index = static_cast<int>(out->rounds.size()) + 1;
    const std::optional<RoundRecord> finished = log.Finished(index);
    if (finished && finished->round.frames) {
      ResumeRound(diagnoser, *finished, index, candidates, state, out);
      progress->Resume(1);
      ++steps;
      continue;
    }
    progress->Begin("round " + std::to_string(index) + ", a frame the job's statements determine");
    Fitted& current = state->current;
    ScoredRound scored =
        diagnoser.Score(current, &state->done, &out->untestable, /*frames_only=*/true);
    scored.round.frames = true;
    Fitted with_cv;
    const int tried = diagnoser.TestFrame(current, &scored, &with_cv);
    if (tried < 0) break;
    const CandidateFinding& chosen = scored.round.candidates[tried];
    const CandidateEffect& c = *scored.testable[tried];
    state->done.insert(c.effect.name);
    if (chosen.accepted) {
      scored.round.accepted = chosen.name;
      out->accepted.push_back(diagnoser.Describe(c, chosen, with_cv, current));
      out->accepted.back().frame = true;
      current = std::move(with_cv);
    }
    log.Keep(index, RecordOf(scored.round, *out, *state, chosen.accepted));
    out->rounds.push_back(std::move(scored.round));
    progress->Advance();
    ++steps;
  }
  return steps;
}

}  // namespace

DiagnosisResult DiagnoseWorkcell(const WorkcellProblem& spec, const Recording& recording,
                                 const SolverMaker& make_solver,
                                 const std::vector<CandidateEffect>& candidates,
                                 const DiagnosisOptions& options, const std::string& origin,
                                 Checkpoint* checkpoint) {
  DiagnosisResult out;
  out.job = origin;
  const NoiseModel noise = BuildNoiseModel(recording, spec.noise);
  CheckInputs(noise, recording, options, origin, &out.noise_source);
  WorkcellProblem all = spec;
  for (const auto& c : candidates) all.effects.push_back(c.effect);
  const WorkcellData data = PrepareWorkcellData(all, recording);  // with every sample's facts
  const std::vector<Regressor> regressors =
      SampleRegressors(recording, data.facts, options.link_masses_kg, spec.gravity_base);
  const Diagnoser diagnoser(recording, make_solver, candidates, options, noise, data);

  RoundState state;
  {
    Progress geometry("fitting the geometry alone", 1);
    state.current = Fit(spec, recording, make_solver, options.folds);
    geometry.Advance();
  }
  out.geometric = state.current.summary;
  const HeldOut geometric_held_out = state.current.result.held_out;
  out.floor_rms_mm = FloorRms(state.current, recording);
  {
    const CandidateLinearization lin =
        LinearizeWithCandidate(spec, recording, data, noise, state.current.result.estimate, false);
    out.regressors = CorrelateRegressors(lin, recording, regressors);
    out.durbin_watson = DurbinWatsonByAxis(lin, recording);
  }
  // The rounds of the physics and of the frames, and the final fit without each camera, each a
  // step of about a round's time; the physics' rounds end sooner where one accepts nothing.
  const int frame_rounds = static_cast<int>(
      std::count_if(candidates.begin(), candidates.end(), [](const auto& c) { return c.frame; }));
  const int last_steps = spec.leave_one_camera_out ? 1 : 0;
  Progress progress("diagnosis step", options.max_effects + frame_rounds + last_steps,
                    Progress::Length::kAtMost);
  RoundLog log(checkpoint);
  const int physics_steps =
      RunPhysicsRounds(diagnoser, candidates, options, log, &state, &progress, &out);
  progress.SetTotal(physics_steps + frame_rounds + last_steps);
  const int frame_steps = RunFrameRounds(diagnoser, candidates, log, &state, &progress, &out);
  progress.SetTotal(physics_steps + frame_steps + last_steps);
  const Fitted& current = state.current;
  out.final = current.summary;
  out.held_out_gain = CompareHeldOut(geometric_held_out, current.result.held_out);
  out.final_fit = current.result;
  out.final_spec = current.spec;
  if (spec.leave_one_camera_out) {
    // The final fit as `cellmetry run` reports it: each camera left out in turn too.
    progress.Begin("identifying the final model without each camera in turn");
    // Its cross-validation is the current fit's (the same model on the same data).
    WorkcellProblem final_spec = current.spec;
    final_spec.leave_one_camera_out = true;
    final_spec.folds = 0;
    out.final_fit = IdentifyWorkcell(final_spec, recording, make_solver);
    out.final_fit.held_out = current.result.held_out;
    progress.Advance();
  }
  GroupFindings(options, &out);
  // Without an accepted effect the model is the geometry, whose findings are already known.
  out.unexplained = diagnoser.Unexplained(
      current.summary,
      out.accepted.empty() ? out.regressors : diagnoser.Regressors(current, regressors));
  return out;
}

}  // namespace cellmetry
