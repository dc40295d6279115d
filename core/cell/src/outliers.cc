// Gross outliers (outliers.h): the robust-scale chi-square test and the recording without them.
#include "cellmetry/cell/outliers.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "cellmetry/basics/statistics.h"

namespace cellmetry {
namespace {

constexpr double kGrossSigmas = 10.0;
constexpr size_t kMinGroupRows = 10;

// One row as the test reads it, from either source (the result's rows, or a problem's
// measurement blocks and residuals): its group's keys, where it came from, its |r|^2.
struct TestedRow {
  const std::string* camera;
  const std::string* target;
  bool rotation;
  int observation;
  int sample;
  double squared_norm;
};

// The ResidualRow of a result as the test reads it.
TestedRow Tested(const ResidualRow& row) {
  return {&row.camera,     &row.target, row.kind == ResidualKind::kRotation,
          row.observation, row.sample,  row.normalized.squaredNorm()};
}

// Each row's group scale (outliers.h); `row_at(i)` gives row i as a TestedRow.
template <class RowAt>
std::vector<double> ScalesOf(size_t num_rows, const RowAt& row_at) {
  // The scale per camera, target and kind: a world board's repeated views scatter far less than
  // a carried board's, and one scale for both flags every carried observation.
  using Group = std::tuple<std::string, std::string, bool>;
  // Each row's group looked up once, first among the few groups used last (a capture's rows
  // cycle through its cameras), then in the map: a map of three strings per row, twice, was
  // most of the test's time.
  std::map<Group, int> index;
  std::vector<std::vector<double>> values;
  std::vector<TestedRow> first_row;  // per group, a row of it
  std::vector<int> recent;           // the groups used last, newest first
  std::vector<int> group_of(num_rows);
  for (size_t i = 0; i < num_rows; ++i) {
    const TestedRow row = row_at(i);
    int group = -1;
    for (size_t k = 0; k < recent.size() && group < 0; ++k) {
      const TestedRow& other = first_row[recent[k]];
      if (*row.camera == *other.camera && *row.target == *other.target &&
          row.rotation == other.rotation) {
        group = recent[k];
        recent.erase(recent.begin() + static_cast<std::ptrdiff_t>(k));
      }
    }
    if (group < 0) {
      const auto [it, added] = index.emplace(Group{*row.camera, *row.target, row.rotation},
                                             static_cast<int>(values.size()));
      if (added) {
        values.emplace_back();
        first_row.push_back(row);
      }
      group = it->second;
      if (recent.size() == 8) recent.pop_back();
    }
    recent.insert(recent.begin(), group);
    group_of[i] = group;
    values[group].push_back(row.squared_norm);
  }
  std::vector<double> scale(values.size());
  for (size_t g = 0; g < values.size(); ++g) {
    // Too few rows for a scale of their own: not tested.
    scale[g] = values[g].size() < kMinGroupRows
                   ? 0.0
                   : Median(std::move(values[g])) / ChiSquareQuantile(0.5, 3);
  }
  std::vector<double> out;
  out.reserve(num_rows);
  for (int g : group_of) out.push_back(scale[g]);
  return out;
}

// The rows that fail the test at `alpha` (outliers.h); `row_at` as for ScalesOf.
template <class RowAt>
std::vector<Outlier> OutliersOf(size_t num_rows, const RowAt& row_at, const Recording& recording,
                                double alpha) {
  std::vector<Outlier> out;
  const std::vector<double> scale = ScalesOf(num_rows, row_at);
  // Gross: beyond chance (Bonferroni) and beyond kGrossSigmas robust standard deviations on
  // every axis together; real recordings' residuals are heavy-tailed where the model is short
  // (exp_a, sim_b), and chance alone flagged a quarter of sim_b's observations.
  const double threshold =
      std::max(ChiSquareQuantile(1.0 - alpha / static_cast<double>(num_rows), 3),
               3.0 * kGrossSigmas * kGrossSigmas);
  for (size_t i = 0; i < num_rows; ++i) {
    if (!(scale[i] > 0.0)) continue;
    const TestedRow row = row_at(i);
    const double score = row.squared_norm / scale[i];
    if (score <= threshold) continue;
    const Observation& obs = recording.observations[row.observation];
    out.push_back({obs.line, row.sample, *row.camera, *row.target,
                   row.rotation ? "rotation" : "position", score, threshold});
  }
  return out;
}

// An assembled workcell's measurement blocks with their whitened residuals as TestedRows (not
// the result's rows: workcell_fit.cc's MeasurementRows makes those).
struct ProblemRows {
  ProblemRows(const AssembledWorkcell& assembled, const Eigen::VectorXd& whitened)
      : infos(assembled.problem.residual_infos()), labels(assembled.labels),
        first_row(assembled.problem.residual_rows()), r(whitened), count(assembled.labels.size()) {}
  TestedRow operator()(size_t b) const {
    const MeasurementLabel& label = labels[b];
    return {&label.camera,     &label.target, infos[b].kind == ResidualInfo::Kind::kRotation,
            label.observation, label.sample,  r.segment<3>(first_row[b]).squaredNorm()};
  }
  const std::vector<ResidualInfo>& infos;
  const std::vector<MeasurementLabel>& labels;
  const std::vector<int>& first_row;
  const Eigen::VectorXd& r;
  size_t count = 0;
};

}  // namespace

std::vector<double> RobustScales(const std::vector<ResidualRow>& rows) {
  return ScalesOf(rows.size(), [&](size_t i) { return Tested(rows[i]); });
}

std::vector<double> RobustScales(const AssembledWorkcell& assembled,
                                 const Eigen::VectorXd& whitened) {
  const ProblemRows rows(assembled, whitened);
  return ScalesOf(rows.count, rows);
}

std::vector<Outlier> FindOutliers(const std::vector<ResidualRow>& rows, const Recording& recording,
                                  double alpha) {
  return OutliersOf(
      rows.size(), [&](size_t i) { return Tested(rows[i]); }, recording, alpha);
}

std::vector<Outlier> FindOutliers(const AssembledWorkcell& assembled,
                                  const Eigen::VectorXd& whitened, const Recording& recording,
                                  double alpha) {
  const ProblemRows rows(assembled, whitened);
  return OutliersOf(rows.count, rows, recording, alpha);
}

Recording WithoutOutliers(const Recording& recording, const std::vector<Outlier>& outliers) {
  std::set<int> lines;
  std::set<std::tuple<int, std::string, std::string>> unlined;
  for (const auto& o : outliers) {
    if (o.line > 0) {
      lines.insert(o.line);
    } else {
      unlined.insert({o.sample, o.camera, o.target});
    }
  }
  Recording out = recording;
  out.observations.clear();
  for (const auto& obs : recording.observations) {
    const bool gone = obs.line > 0 ? lines.count(obs.line) > 0
                                   : unlined.count({obs.sample, obs.camera, obs.target}) > 0;
    if (!gone) out.observations.push_back(obs);
  }
  return out;
}

void NumberByOriginal(const Recording& original, const Recording& kept,
                      std::vector<ResidualRow>* rows) {
  std::vector<int> index_in_original(kept.observations.size());
  size_t at = 0;
  for (size_t k = 0; k < kept.observations.size(); ++k) {
    const Observation& obs = kept.observations[k];
    auto same = [&](const Observation& o) {
      return o.line == obs.line && o.sample == obs.sample && o.camera == obs.camera &&
             o.target == obs.target;
    };
    while (at < original.observations.size() && !same(original.observations[at])) ++at;
    if (at == original.observations.size()) {
      throw std::logic_error("NumberByOriginal: an observation kept is not in the original");
    }
    index_in_original[k] = static_cast<int>(at++);
  }
  for (ResidualRow& row : *rows) row.observation = index_in_original.at(row.observation);
}

std::string OutliersCsv(const std::vector<Outlier>& outliers) {
  std::ostringstream out;
  out << "line,sample,camera,target,kind,score,threshold\n";
  for (const auto& o : outliers) {
    char numbers[64];
    std::snprintf(numbers, sizeof(numbers), "%.4g,%.4g", o.score, o.threshold);
    out << o.line << "," << o.sample << "," << o.camera << "," << o.target << "," << o.kind << ","
        << numbers << "\n";
  }
  return out.str();
}

}  // namespace cellmetry
