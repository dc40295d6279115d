// Writing a visual homing result (homing_io.h).
#include "cellmetry/cell/homing_io.h"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <sstream>

#include "cellmetry/formats/atomic_file.h"
#include "result_yaml.h"

namespace cellmetry {
namespace {

std::string Format(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof(text), format, a, b, c, d);
  return text;
}

}  // namespace

std::string HomingYaml(const HomingResult& r) {
  const double inc = r.increment_rad;
  YAML::Emitter out;
  out << YAML::Comment("cellmetry visual homing: true motor angle = command + offset");
  out << YAML::BeginMap;
  out << YAML::Key << "increment_rad" << YAML::Value << inc;
  out << YAML::Key << "positions_available" << YAML::Value << r.positions;
  out << YAML::Key << "interval" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "offset_rad" << YAML::Value << YAML::Flow << Vec(r.interval_offset_rad);
  out << YAML::Key << "offset_increments" << YAML::Value << YAML::Flow
      << Vec(r.interval_offset_rad / (inc > 0 ? inc : 1.0));
  out << YAML::Key << "width_increments" << YAML::Value << YAML::Flow
      << Vec(r.interval_width_rad / (inc > 0 ? inc : 1.0));
  out << YAML::Key << "positions_used" << YAML::Value << YAML::Flow << r.runs.front().samples;
  out << YAML::Key << "validated" << YAML::Value << r.validated;
  out << YAML::Key << "validation" << YAML::Value << r.validation;
  out << YAML::EndMap;
  out << YAML::Key << "least_squares" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "offset_rad" << YAML::Value << YAML::Flow << Vec(r.lsq_offset_rad);
  out << YAML::Key << "sigma_rad" << YAML::Value << YAML::Flow << Vec(r.lsq_sigma_rad);
  out << YAML::Key << "offset_increments" << YAML::Value << YAML::Flow
      << Vec(r.lsq_offset_rad / (inc > 0 ? inc : 1.0));
  out << YAML::Key << "sigma_increments" << YAML::Value << YAML::Flow
      << Vec(r.lsq_sigma_rad / (inc > 0 ? inc : 1.0));
  out << YAML::EndMap;
  out << YAML::Key << "warnings" << YAML::Value << YAML::Flow << r.warnings;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void WriteHomingResult(const HomingResult& result, const std::string& folder,
                       const std::function<void(const std::string& staging)>& extra) {
  StagedDirectory out(folder, "homing");
  AtomicWriteFile(out.File("homing.yaml"), HomingYaml(result));
  if (extra) extra(out.staging());
  out.Commit();
}

std::string HomingSummary(const HomingResult& r) {
  const double inc = r.increment_rad > 0 ? r.increment_rad : 1.0;
  std::ostringstream out;
  out << "Visual homing (" << r.positions << " positions available)\n";
  out << "  interval algorithm: offset "
      << Format("(%.2f, %.2f, %.2f) increments", r.interval_offset_rad[0] / inc,
                r.interval_offset_rad[1] / inc, r.interval_offset_rad[2] / inc)
      << ", from " << r.runs.front().samples.size() << " positions, final interval width "
      << Format("(%.2f, %.2f, %.2f) increments", r.interval_width_rad[0] / inc,
                r.interval_width_rad[1] / inc, r.interval_width_rad[2] / inc)
      << "\n  " << r.validation << "\n";
  out << "  least squares: offset "
      << Format("(%.2f, %.2f, %.2f)", r.lsq_offset_rad[0] / inc, r.lsq_offset_rad[1] / inc,
                r.lsq_offset_rad[2] / inc)
      << Format(" +- (%.2f, %.2f, %.2f) increments (1 sigma)", r.lsq_sigma_rad[0] / inc,
                r.lsq_sigma_rad[1] / inc, r.lsq_sigma_rad[2] / inc)
      << "\n";
  for (const auto& w : r.warnings) out << "  warning: " << w << "\n";
  return out.str();
}

}  // namespace cellmetry
