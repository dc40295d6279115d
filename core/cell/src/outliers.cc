// Gross outliers (outliers.h): the robust-scale chi-square test and the recording without them.
#include "cellmetry/cell/outliers.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "cellmetry/basics/statistics.h"

namespace cellmetry {
namespace {

constexpr double kGrossSigmas = 10.0;
constexpr size_t kMinGroupRows = 10;

}  // namespace

std::vector<double> RobustScales(const std::vector<ResidualRow>& rows) {
  // The scale per camera, target and kind: a world board's repeated views scatter far less than
  // a carried board's, and one scale for both flags every carried observation.
  using Group = std::tuple<std::string, std::string, std::string>;
  std::map<Group, std::vector<double>> groups;
  for (const auto& row : rows) {
    groups[{row.camera, row.target, row.kind}].push_back(row.normalized.squaredNorm());
  }
  std::map<Group, double> scale;
  for (const auto& [key, values] : groups) {
    // Too few rows for a scale of their own: not tested.
    scale[key] = values.size() < kMinGroupRows ? 0.0 : Median(values) / ChiSquareQuantile(0.5, 3);
  }
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(scale.at({row.camera, row.target, row.kind}));
  return out;
}

std::vector<Outlier> FindOutliers(const std::vector<ResidualRow>& rows, const Recording& recording,
                                  double alpha) {
  std::vector<Outlier> out;
  const std::vector<double> scale = RobustScales(rows);
  // Gross: beyond chance (Bonferroni) and beyond kGrossSigmas robust standard deviations on
  // every axis together; real recordings' residuals are heavy-tailed where the model is short
  // (exp_a, sim_b), and chance alone flagged a quarter of sim_b's observations.
  const double threshold =
      std::max(ChiSquareQuantile(1.0 - alpha / static_cast<double>(rows.size()), 3),
               3.0 * kGrossSigmas * kGrossSigmas);
  for (size_t i = 0; i < rows.size(); ++i) {
    const ResidualRow& row = rows[i];
    if (!(scale[i] > 0.0)) continue;
    const double score = row.normalized.squaredNorm() / scale[i];
    if (score <= threshold) continue;
    const Observation& obs = recording.observations[row.observation];
    out.push_back({obs.line, row.sample, row.camera, row.target, row.kind, score, threshold});
  }
  return out;
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
