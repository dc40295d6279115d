// The commands file (commands_csv.h).
#include "cellmetry/compensation/commands_csv.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "cellmetry/basics/text.h"
#include "cellmetry/exports/export_header.h"

namespace cellmetry {
namespace {

std::string Exact(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string Short(double value) {
  if (!std::isfinite(value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string Short(const std::optional<double>& value) { return value ? Short(*value) : ""; }

// `text` as one CSV cell: quoted when it holds a comma or a quote (quotes doubled).
std::string Cell(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  }
  return quoted + "\"";
}

std::string Header(int joints) {
  std::string header = "id,line,status";
  for (int j = 1; j <= joints; ++j) header += ",q" + std::to_string(j) + "_rad";
  header += ",error_mm,error_rad,sigma_mm,sigma_rad,uncompensated_mm,uncompensated_rad";
  for (int j = 1; j <= joints; ++j) header += ",approach_j" + std::to_string(j);
  return header + ",beyond_calibration,reason\n";
}

// The joints a command puts beyond the calibration's ranges, "2 5"; "" for none.
std::string JointList(const std::vector<int>& joints) {
  std::string text;
  for (int j : joints) text += (text.empty() ? "" : " ") + std::to_string(j);
  return text;
}

// The calibration's joint ranges in degrees, "-5.0..84.0, 6.0..138.0, ...".
std::string RangesInDegrees(const JointRangesRad& ranges_rad) {
  std::string text;
  for (const auto& [min_rad, max_rad] : ranges_rad) {
    text += (text.empty() ? "" : ", ") + Degrees(min_rad) + ".." + Degrees(max_rad);
  }
  return text;
}

}  // namespace

std::string CompensatedCommandsCsv(const CompensationChain& chain,
                                   const std::vector<CompensatedCommand>& commands,
                                   const std::vector<std::string>& comments) {
  const int joints = chain.model->num_joints();
  std::ostringstream out;
  out << CommentLines(comments, "# ") << Header(joints);
  for (const auto& c : commands) {
    out << Cell(c.target->id) << "," << c.target->line << "," << (c.refused ? "refused" : "ok");
    for (int j = 0; j < joints; ++j) out << "," << (c.refused ? "" : Exact(c.q_rad[j]));
    out << "," << Short(c.error_mm) << "," << Short(c.error_rad) << "," << Short(c.sigma_mm) << ","
        << Short(c.sigma_rad) << "," << Short(c.uncompensated_mm) << ","
        << Short(c.uncompensated_rad);
    for (int j = 0; j < joints; ++j) {
      out << "," << (j < static_cast<int>(c.approach.size()) ? std::to_string(c.approach[j]) : "");
    }
    out << "," << JointList(c.joints_beyond_calibration) << "," << Cell(c.reason) << "\n";
  }
  return out.str();
}

std::vector<std::string> CompensationComments(const CalibratedCell& cell,
                                              const CompensationChain& chain) {
  const CalibratedRobot& robot = ChooseRobot(cell, chain.robot);
  std::vector<std::string> lines =
      ExportHeader(cell, "compensated commands", &robot, "cellmetry compensate");
  lines.push_back("targets: tool '" + chain.tool +
                  "' in the world frame of the result (mm, "
                  "rotation vectors in rad); commands: the controller's joint readings (rad)");
  for (size_t k = 0; k < chain.effects.size(); ++k) {
    std::string values;
    for (const auto& e : cell.effects) {
      if (e.name != chain.effect_names[k]) continue;
      for (const auto& p : e.parameters) {
        values += (values.empty() ? "" : ", ") + p.name + " = " + ValueWithSigma(p);
      }
    }
    lines.push_back("effect applied: " + chain.effect_names[k] + " (" + values + ")");
  }
  if (chain.effects.empty()) lines.push_back("effects applied: none (the result fitted none)");
  lines.push_back(
      "sigma: first-order, from the result's covariance of the base, the tool, the "
      "freed model and effect parameters; not the controller's repeatability");
  lines.push_back(
      chain.calibrated_joint_ranges_rad.empty()
          ? "beyond_calibration: not checked (the result does not record the calibration's "
            "joint ranges)"
          : "beyond_calibration: the joints a command puts outside the ranges the calibration's "
            "poses span (deg: " +
                RangesInDegrees(chain.calibrated_joint_ranges_rad) +
                "); there the model is extrapolated and sigma holds only what it contains");
  return lines;
}

}  // namespace cellmetry
