// The marker comparison over seeds, with intervals and a recommendation (marker_comparison.h).
#include <nlohmann/json.hpp>
#include <sstream>

#include "cellmetry/basics/progress.h"
#include "cellmetry/experiments/intervals.h"
#include "cellmetry/experiments/marker_comparison.h"
#include "cellmetry/experiments/solver_compare.h"
#include "cellmetry/formats/checkpoint.h"

namespace cellmetry {
namespace {

// One figure of one detector over the seeds.
template <typename Figure>
std::vector<double> Over(const std::vector<std::vector<MarkerRow>>& per_seed, size_t detector,
                         Figure figure) {
  std::vector<double> values;
  for (const auto& rows : per_seed) values.push_back(figure(rows[detector]));
  return values;
}

nlohmann::json ToJson(const std::vector<MarkerRow>& rows) {
  nlohmann::json out = nlohmann::json::array();
  auto xyz = [](const Eigen::Vector3d& v) { return std::vector<double>{v.x(), v.y(), v.z()}; };
  for (const MarkerRow& r : rows) {
    out.push_back({{"label", r.label},
                   {"repeatability_mm", xyz(r.repeatability_mm)},
                   {"floor_mm", xyz(r.floor_mm)},
                   {"static_bias_mm", r.static_bias_mm},
                   {"workspace_rms_mm", r.workspace_rms_mm},
                   {"captures_found", r.captures_found},
                   {"positions_found", r.positions_found},
                   {"positions", r.positions},
                   {"ms_per_frame", r.ms_per_frame}});
  }
  return out;
}

std::vector<MarkerRow> FromJson(const nlohmann::json& rows) {
  std::vector<MarkerRow> out;
  auto xyz = [](const nlohmann::json& v) {
    const auto a = v.get<std::vector<double>>();
    return Eigen::Vector3d(a.at(0), a.at(1), a.at(2));
  };
  for (const auto& j : rows) {
    MarkerRow r;
    r.label = j.at("label").get<std::string>();
    r.repeatability_mm = xyz(j.at("repeatability_mm"));
    r.floor_mm = xyz(j.at("floor_mm"));
    r.static_bias_mm = j.at("static_bias_mm").get<double>();
    r.workspace_rms_mm = j.at("workspace_rms_mm").get<double>();
    r.captures_found = j.at("captures_found").get<int>();
    r.positions_found = j.at("positions_found").get<int>();
    r.positions = j.at("positions").get<int>();
    r.ms_per_frame = j.at("ms_per_frame").get<double>();
    out.push_back(r);
  }
  return out;
}

}  // namespace

std::vector<std::vector<MarkerRow>> CompareMarkersOverSeeds(const MarkerComparisonSpec& spec,
                                                            Registry& registry,
                                                            const std::string& checkpoint) {
  std::vector<std::vector<MarkerRow>> per_seed;
  Checkpoint done(checkpoint, spec.fingerprint);
  Progress progress("marker comparison seed", spec.seeds);
  for (int i = 0; i < spec.seeds; ++i) {
    MarkerComparisonSpec one = spec;
    one.seed = spec.seed + static_cast<unsigned>(i);
    const std::string key = std::to_string(one.seed);
    if (const nlohmann::json* piece = done.Find(key)) {
      try {
        per_seed.push_back(FromJson(*piece));
        progress.Resume(1);
        continue;
      } catch (const std::exception&) {
        // a row that does not read back is run again
      }
    }
    per_seed.push_back(CompareMarkers(one, registry));
    done.Put(key, ToJson(per_seed.back()));
    progress.Advance();
  }
  return per_seed;
}

std::string MarkerSeedsMarkdown(const MarkerComparisonSpec& spec,
                                const std::vector<std::vector<MarkerRow>>& per_seed) {
  std::ostringstream out;
  const std::string one = MarkerTableMarkdown(spec, per_seed.front());
  out << one.substr(0, one.find("\n\n") + 2);  // the rig and render line
  out << per_seed.size() << " seeds (" << spec.seed << " to " << spec.seed + per_seed.size() - 1
      << "): mean [95 % t-interval].\n\n";
  out << "| detector | sigma depth (mm) | depth / floor | bias at the static pose (mm) | "
         "workspace RMS error (mm) | detected (%) | ms / frame |\n";
  out << "|---|---|---|---|---|---|---|\n";
  std::vector<Contender> contenders;
  for (size_t d = 0; d < per_seed.front().size(); ++d) {
    const auto depth = Over(per_seed, d, [](const MarkerRow& r) { return r.repeatability_mm.z(); });
    const auto ratio = Over(per_seed, d, [](const MarkerRow& r) {
      return r.floor_mm.z() > 0 ? r.repeatability_mm.z() / r.floor_mm.z() : 0.0;
    });
    const auto bias = Over(per_seed, d, [](const MarkerRow& r) { return r.static_bias_mm; });
    const auto rms = Over(per_seed, d, [](const MarkerRow& r) { return r.workspace_rms_mm; });
    const auto rate = Over(per_seed, d, [](const MarkerRow& r) {
      return r.positions > 0 ? 100.0 * r.positions_found / r.positions : 0.0;
    });
    const auto ms = Over(per_seed, d, [](const MarkerRow& r) { return r.ms_per_frame; });
    auto interval = [](const std::vector<double>& values) {
      return IntervalText(values, 1.0, FigureStyle::kFourDigits);
    };
    out << "| " << per_seed.front()[d].label << " | " << interval(depth) << " | " << interval(ratio)
        << " | " << interval(bias) << " | " << interval(rms) << " | " << interval(rate) << " | "
        << interval(ms) << " |\n";
    Contender c{per_seed.front()[d].label, rms, {}};
    for (double v : ms) c.time_s.push_back(v / 1e3);
    contenders.push_back(c);
  }
  out << "\nRecommendation (same: means within 1 %, or the 95 % t-interval of the per-seed "
         "differences contains 0; a tie is called a tie):\n\n- "
      << Recommendation("for this rig, which detector", contenders, "mm workspace RMS error")
      << "\n";
  return out.str();
}

std::string MarkerSeedsCsv(const MarkerComparisonSpec& spec,
                           const std::vector<std::vector<MarkerRow>>& per_seed) {
  std::ostringstream out;
  for (size_t i = 0; i < per_seed.size(); ++i) {
    std::string table = MarkerTableCsv(per_seed[i]);
    std::istringstream lines(table);
    std::string line;
    bool header = true;
    while (std::getline(lines, line)) {
      if (header) {
        if (i == 0) out << "seed," << line << "\n";
        header = false;
        continue;
      }
      out << spec.seed + i << "," << line << "\n";
    }
  }
  return out.str();
}

}  // namespace cellmetry
