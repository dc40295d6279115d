// Where residuals follow something (diagnosis_regressors.h): the recording's regressors, their
// partial correlations with the residuals, and Durbin-Watson per camera axis.
#include "diagnosis_regressors.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "cellmetry/basics/statistics.h"
#include "cellmetry/model/effect_context.h"

namespace cellmetry {
namespace {

const char* kAxes[3] = {"x", "y", "depth"};

bool Varies(const std::vector<double>& values) {
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  return hi > lo + 1e-12 * (1 + std::abs(hi));
}

// The rows of carried targets' position residuals.
bool IsToolPositionRow(const CandidateLinearization& lin, const Recording& recording,
                       Eigen::Index i) {
  const CandidateRow& info = lin.rows[i];
  return info.kind == ResidualInfo::Kind::kPosition && info.label.observation >= 0 &&
         recording.IsCarried(info.label.target);
}

// "1.7 h", "25 min", "90 s".
std::string Duration(double seconds) {
  char text[32];
  if (seconds >= 5400) {
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600);
  } else if (seconds >= 120) {
    std::snprintf(text, sizeof text, "%.0f min", seconds / 60);
  } else {
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  }
  return text;
}

// A step across the longest pause between captures, when the times say there was one: a setup
// left standing (an instrument re-homed, an arm cooled) can come back changed, wherever in the
// run the pause fell. A pause is at least a minute and ten times the median interval.
std::optional<Regressor> StepAcrossPause(const Recording& recording) {
  const size_t n = recording.samples.size();
  std::vector<double> intervals;
  size_t longest_after = 0;
  double longest = 0.0;
  for (size_t i = 0; i + 1 < n; ++i) {
    const auto &t0 = recording.samples[i].time_s, &t1 = recording.samples[i + 1].time_s;
    if (!t0 || !t1) continue;
    intervals.push_back(*t1 - *t0);
    if (*t1 - *t0 > longest) longest = *t1 - *t0, longest_after = i;
  }
  if (intervals.size() < 3) return std::nullopt;
  std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
  const double median = intervals[intervals.size() / 2];
  if (longest < 60.0 || longest < 10.0 * median) return std::nullopt;
  Regressor step{"a step across the " + Duration(longest) + " pause after capture " +
                     std::to_string(longest_after),
                 std::vector<double>(n, 0.0)};
  for (size_t i = longest_after + 1; i < n; ++i) step.per_sample[i] = 1.0;
  return step;
}

}  // namespace

std::vector<Regressor> SampleRegressors(const Recording& recording,
                                        const std::vector<SampleFacts>& facts,
                                        const std::vector<double>& link_masses_kg,
                                        const Eigen::Vector3d& gravity_base) {
  const size_t n = recording.samples.size();
  std::vector<Regressor> out;
  size_t joints = 0;
  for (const auto& f : facts) joints = std::max(joints, f.q.size());
  for (size_t j = 0; j < joints; ++j) {
    const std::string joint = "joint " + std::to_string(j + 1);
    Regressor angle{joint + " angle", std::vector<double>(n, NAN)};
    Regressor torque{joint + " gravity torque", std::vector<double>(n, NAN)};
    Regressor approach{joint + " approach direction", std::vector<double>(n, NAN)};
    for (size_t i = 0; i < n; ++i) {
      const SampleFacts& f = facts[i];
      if (j >= f.q.size()) continue;
      angle.per_sample[i] = f.q[j];
      approach.per_sample[i] = f.approach[j];
      std::vector<double> masses = link_masses_kg;
      masses.resize(f.q.size(), 1.0);
      const auto torques = ContextGravityTorques(ContextOf(f, gravity_base), masses);
      if (j < torques.size()) torque.per_sample[i] = torques[j];
    }
    for (auto* r : {&angle, &torque, &approach}) {
      if (Varies(r->per_sample)) out.push_back(*r);
    }
  }
  Regressor order{"capture order", {}}, time{"time", {}}, temperature{"temperature", {}},
      payload{"payload", {}};
  for (size_t i = 0; i < n; ++i) {
    order.per_sample.push_back(static_cast<double>(i));
    time.per_sample.push_back(recording.samples[i].time_s.value_or(NAN));
    temperature.per_sample.push_back(recording.samples[i].temperature_c.value_or(NAN));
    payload.per_sample.push_back(recording.samples[i].payload_kg.value_or(NAN));
  }
  for (auto* r : {&order, &time, &temperature, &payload}) {
    if (Varies(r->per_sample)) out.push_back(*r);
  }
  // Steps in capture order at every tenth of the run: a camera knocked or a fixture shifted
  // mid-run jumps once, which a linear trend in capture order follows only in part (0.87 of a
  // step at the middle).
  for (int tenth = 1; tenth < 10; ++tenth) {
    const size_t at = n * tenth / 10;
    Regressor step{"a step after capture " + std::to_string(at), std::vector<double>(n, 0.0)};
    for (size_t i = at; i < n; ++i) step.per_sample[i] = 1.0;
    if (Varies(step.per_sample)) out.push_back(step);
  }
  if (auto pause = StepAcrossPause(recording)) out.push_back(std::move(*pause));
  return out;
}

namespace {

// The value of regressor k (sample regressors, then measured depth, image x, image y) on a row.
double RowValue(const CandidateLinearization& lin, const Recording& recording,
                const std::vector<Regressor>& regressors, size_t k, Eigen::Index row) {
  const Observation& obs = recording.observations[lin.rows[row].label.observation];
  if (k < regressors.size()) return regressors[k].per_sample[recording.SampleIndex(obs.sample)];
  if (k == regressors.size()) return obs.position_mm.z();
  return obs.position_mm[k - regressors.size() - 1] / obs.position_mm.z();
}

// A partial correlation and its Fisher z (atanh(r) sqrt(n - 3), standard normal without
// correlation), over the n rows that know the regressor.
struct Correlation {
  RegressorFinding finding;
  double z = 0.0;
};

// Partial correlation of the residuals on `rows` with regressor values `x` (on those rows),
// after projecting out span(Q); none when too few rows know the regressor.
std::optional<Correlation> Correlate(const CandidateLinearization& lin, const Eigen::MatrixXd& Q,
                                     const std::vector<Eigen::Index>& rows,
                                     const std::vector<double>& values) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(lin.r.size()), r = Eigen::VectorXd::Zero(lin.r.size());
  std::vector<Eigen::Index> known;
  double mean = 0.0;
  for (size_t k = 0; k < rows.size(); ++k) {
    if (!std::isfinite(values[k])) continue;
    x[rows[k]] = values[k];
    r[rows[k]] = lin.r[rows[k]];
    mean += values[k];
    known.push_back(rows[k]);
  }
  if (known.size() < 10) return std::nullopt;
  mean /= known.size();
  for (auto i : known) x[i] -= mean;
  const Eigen::VectorXd x_perp = ProjectOut(Q, x);
  const double denominator = x_perp.norm() * r.norm();
  if (!(denominator > 0)) return std::nullopt;
  Correlation out;
  out.finding.partial_correlation = r.dot(x_perp) / denominator;
  const double c = std::min(std::abs(out.finding.partial_correlation), 0.999999);
  out.z = std::atanh(c) * std::sqrt(double(known.size()) - 3.0);
  out.finding.p_value = 2.0 * NormalSurvival(out.z);
  return out;
}

}  // namespace

std::vector<RegressorFinding> CorrelateRegressors(const CandidateLinearization& lin,
                                                  const Recording& recording,
                                                  const std::vector<Regressor>& regressors) {
  const Eigen::MatrixXd Q = OrthonormalBasis(lin.J_model);
  std::vector<std::string> names;
  for (const auto& r : regressors) names.push_back(r.name);
  names.insert(names.end(), {"measured depth", "image x", "image y"});
  // Every regressor over all cameras' rows, and over each camera's alone (a camera that moved,
  // or one whose depth is off, shows in its own rows).
  std::vector<std::string> scopes = {""};
  if (recording.cameras.size() > 1)
    scopes.insert(scopes.end(), recording.cameras.begin(), recording.cameras.end());
  std::vector<RegressorFinding> findings;
  for (const auto& scope : scopes) {
    // Over all cameras: the carried targets' rows (robot physics). Per camera: every position
    // row of that camera, the world target's too (a camera that moved shifts them all).
    std::vector<Eigen::Index> rows[3];
    for (Eigen::Index i = 0; i < lin.r.size(); ++i) {
      const bool position =
          lin.rows[i].kind == ResidualInfo::Kind::kPosition && lin.rows[i].label.observation >= 0;
      if (scope.empty() ? IsToolPositionRow(lin, recording, i)
                        : position && lin.rows[i].label.camera == scope) {
        rows[lin.row_axis[i]].push_back(i);
      }
    }
    const std::string where = scope.empty() ? "" : " in " + scope;
    for (size_t k = 0; k < names.size(); ++k) {
      // Each axis alone, and the three together (Fisher's z added in squares, chi-square with 3
      // dof): a camera knocked sideways and down spreads its shift over the axes, which each
      // alone may not carry past the multiple-testing correction.
      double z2 = 0.0, r2_weighted = 0.0;
      int axes = 0;
      for (int axis = 0; axis < 3; ++axis) {
        std::vector<double> values;
        for (auto i : rows[axis]) values.push_back(RowValue(lin, recording, regressors, k, i));
        auto c = Correlate(lin, Q, rows[axis], values);
        if (!c) continue;
        z2 += c->z * c->z;
        r2_weighted += c->finding.partial_correlation * c->finding.partial_correlation;
        ++axes;
        c->finding.regressor = names[k] + where;
        c->finding.axis = kAxes[axis];
        findings.push_back(c->finding);
      }
      if (axes < 2) continue;
      RegressorFinding all;
      all.regressor = names[k] + where;
      all.axis = "x, y and depth";
      all.partial_correlation = std::sqrt(r2_weighted / axes);  // RMS over the axes, unsigned
      all.p_value = ChiSquareSurvival(z2, axes);
      findings.push_back(all);
    }
  }
  for (auto& f : findings) f.p_value = std::min(1.0, f.p_value * findings.size());
  // Most significant first (a strong correlation over a few rows can mean less than a weaker
  // one over many).
  std::sort(findings.begin(), findings.end(), [](const auto& a, const auto& b) {
    return std::make_pair(a.p_value, -std::abs(a.partial_correlation)) <
           std::make_pair(b.p_value, -std::abs(b.partial_correlation));
  });
  return findings;
}

std::map<std::string, double> DurbinWatsonByAxis(const CandidateLinearization& lin,
                                                 const Recording& recording) {
  std::map<std::string, double> out;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<std::pair<int, double>> ordered;  // (sample index, residual)
    for (Eigen::Index i = 0; i < lin.r.size(); ++i) {
      if (lin.row_axis[i] != axis || !IsToolPositionRow(lin, recording, i)) continue;
      ordered.push_back({recording.SampleIndex(lin.rows[i].label.sample), lin.r[i]});
    }
    if (ordered.size() < 3) continue;
    std::stable_sort(ordered.begin(), ordered.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<double> e;
    for (const auto& [sample, value] : ordered) e.push_back(value);
    out[kAxes[axis]] = DurbinWatson(e);
  }
  return out;
}

}  // namespace cellmetry
