#include "cellmetry/cell/kinematic_result_io.h"

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

nlohmann::json ValidationJson(const KinematicValidation& v) {
  return {{"recording", v.recording},
          {"before_mm", RmsJson(v.before)},
          {"after_mm", RmsJson(v.after)},
          {"mean_after_mm", v.mean_after_mm},
          {"max_after_mm", v.max_after_mm}};
}

}  // namespace

std::string KinematicResultYaml(const KinematicResult& r) {
  YAML::Emitter out;
  out << YAML::Comment("cellmetry kinematic calibration (" + FormulationName(r.formulation) +
                       ", " + r.solver.solver + "); lengths mm, angles rad");
  out << YAML::BeginMap;
  EmitFrameYaml(out, "camera", r.camera);
  out << YAML::Key << "marker" << YAML::Value << YAML::BeginMap << YAML::Key << "xyz"
      << YAML::Value << YAML::Flow << Vec(r.state.marker_mm) << YAML::Key << "sigma_xyz"
      << YAML::Value << YAML::Flow << Vec(r.marker_sigma_mm) << YAML::EndMap;
  out << YAML::Key << "model" << YAML::Value << YAML::BeginMap;
  for (const auto& p : r.model_parameters) {
    out << YAML::Key << p.name << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "value" << YAML::Value << p.value << YAML::Key << "sigma" << YAML::Value << p.sigma
        << YAML::Key << "unit" << YAML::Value << p.unit;
    if (p.held) out << YAML::Key << "held" << YAML::Value << true;
    out << YAML::EndMap;
  }
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

nlohmann::json KinematicResultJson(const KinematicResult& r,
                                   const std::optional<KinematicValidation>& validation) {
  nlohmann::json j;
  j["format"] = "cellmetry-kinematic-result/1";
  j["formulation"] = FormulationName(r.formulation);
  j["solver"] = SolverJson(r.solver);
  j["samples"] = r.samples;
  j["closed_form_camera"] = {{"xyz_mm", Vec(r.closed_form_camera.T_base_cam.t)},
                             {"rvec_rad", Vec(RvecFromRotation(r.closed_form_camera.T_base_cam.R))},
                             {"rms_mm", r.closed_form_camera.rms_mm},
                             {"points", r.closed_form_camera.points}};
  j["camera"] = {{"parent", "base"},
                 {"xyz_mm", Vec(r.camera.pose.t)},
                 {"rvec_rad", Vec(RvecFromRotation(r.camera.pose.R))},
                 {"sigma_xyz_mm", Vec(r.camera.sigma_mm)},
                 {"sigma_rot_rad", Vec(r.camera.sigma_rad)}};
  j["marker"] = {{"xyz_mm", Vec(r.state.marker_mm)}, {"sigma_xyz_mm", Vec(r.marker_sigma_mm)}};
  j["model_parameters"] = nlohmann::json::array();
  for (const auto& p : r.model_parameters) {
    j["model_parameters"].push_back({{"name", p.name}, {"unit", p.unit}, {"nominal", p.nominal},
                                     {"value", p.value}, {"sigma", p.sigma}, {"held", p.held}});
  }
  AddUncertaintyJson(r.uncertainty, r.unidentifiable, r.strong_correlations, &j);
  j["weakly_identified"] = nlohmann::json::array();
  for (const auto& w : r.weakly_identified) {
    j["weakly_identified"].push_back(
        {{"name", w.name}, {"variance_inflation", w.variance_inflation}, {"partners", w.partners}});
  }
  j["noise_used"] = {{"position_mm", Vec(r.sigma_mm)}, {"source", r.sigma_source}};
  j["residual_rms_mm"] = RmsJson(r.position_rms);
  if (validation) j["validation"] = ValidationJson(*validation);
  j["warnings"] = r.warnings;
  return j;
}

std::string KinematicResidualsCsv(const KinematicProblem& problem, const KinematicResult& r,
                                  const std::vector<PointSample>& samples) {
  std::ostringstream out;
  out << "observation,sample,ex,ey,ez\n";
  out.precision(9);
  for (const auto& s : samples) {
    Eigen::Vector3d p;
    if (!PredictInCamera(*problem.model, r.state, s.q, &p)) continue;
    const Eigen::Vector3d e = p - s.p_cam_mm;
    out << s.observation << "," << s.sample << "," << e.x() << "," << e.y() << "," << e.z() << "\n";
  }
  return out.str();
}

void WriteKinematicResult(const KinematicProblem& problem, const KinematicResult& result,
                          const std::vector<PointSample>& samples,
                          const std::optional<KinematicValidation>& validation,
                          const std::string& folder) {
  StagedDirectory out(folder);
  AtomicWriteFile(out.File("result.yaml"), KinematicResultYaml(result));
  AtomicWriteFile(out.File("result.json"), KinematicResultJson(result, validation).dump(2) + "\n");
  AtomicWriteFile(out.File("residuals.csv"), KinematicResidualsCsv(problem, result, samples));
  out.Commit();
}

std::string KinematicSummary(const KinematicResult& r,
                             const std::optional<KinematicValidation>& validation) {
  std::ostringstream out;
  out << "Kinematic calibration (" << FormulationName(r.formulation) << ", solver "
      << r.solver.solver << ": " << r.solver.iterations << " iterations, "
      << r.solver.stop_reason << ")\n";
  if (r.closed_form_camera.points > 0) {
    out << "  closed-form camera (Kabsch on " << r.closed_form_camera.points
        << " positions, nominal arm): " << Format("RMS %.3f mm", r.closed_form_camera.rms_mm)
        << "\n";
  }
  out << "  camera in base: xyz " << Format("(%.3f, %.3f, %.3f) mm", r.camera.pose.t.x(),
                                            r.camera.pose.t.y(), r.camera.pose.t.z())
      << Format(" +- (%.3f, %.3f, %.3f)", r.camera.sigma_mm.x(), r.camera.sigma_mm.y(),
                r.camera.sigma_mm.z())
      << "\n";
  for (const auto& p : r.model_parameters) {
    if (p.held && p.sigma == 0.0 && p.value == p.nominal) continue;
    const char* format = p.unit == "rad" ? "%.6f +- %.6f " : "%.4f +- %.4f ";
    out << "  " << p.name << " = " << Format(format, p.value, p.sigma) << p.unit
        << Format(p.unit == "rad" ? "  (nominal %.6f)" : "  (nominal %.4f)", p.nominal) << "\n";
  }
  for (const auto& u : r.unidentifiable) {
    out << "  not identifiable from this data: " << u.name << " (" << u.reason << "); held\n";
  }
  for (const auto& w : r.weakly_identified) {
    out << "  barely identified: " << w.name << Format(" (variance inflation %.3g", w.variance_inflation)
        << (w.partners.empty() ? "" : "; moves with " + w.partners) << ")\n";
  }
  out << "  residual RMS " << Format("%.4f mm (x %.4f, y %.4f, depth %.4f)", r.position_rms.norm,
                                     r.position_rms.axis.x(), r.position_rms.axis.y(),
                                     r.position_rms.axis.z())
      << " over " << r.samples << " samples\n";
  if (validation) {
    out << "  fresh positions: RMS " << Format("%.4f mm before, %.4f mm after", validation->before.norm,
                                              validation->after.norm)
        << Format(" (mean %.4f, max %.4f mm)", validation->mean_after_mm, validation->max_after_mm)
        << "\n";
  }
  for (const auto& w : r.warnings) out << "  warning: " << w << "\n";
  return out.str();
}

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

void WriteHomingResult(const HomingResult& result, const std::string& folder) {
  StagedDirectory out(folder);
  AtomicWriteFile(out.File("homing.yaml"), HomingYaml(result));
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
