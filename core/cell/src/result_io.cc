// Writing a WorkcellResult (result_io.h): result.yaml, result.json, residuals.csv, outliers.csv,
// the summary.
#include "cellmetry/cell/result_io.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>
#include <tuple>

#include "cellmetry/cell/joint_ranges.h"
#include "cellmetry/cell/outliers.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/fixed_number.h"
#include "result_yaml.h"

namespace cellmetry {
namespace {

nlohmann::json HeldOutJson(const HeldOut& h) {
  nlohmann::json j = {
      {"folds", h.folds}, {"total_mm", RmsJson(h.total)}, {"total_se_mm", h.total_se_mm}};
  for (const auto& [camera, rms] : h.per_camera) j["per_camera_mm"][camera] = RmsJson(rms);
  return j;
}

nlohmann::json NoiseJson(const NoiseModel& noise) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, n] : noise.entries) {
    j[key.first + "/" + key.second] = {{"position_mm", Vec(n.position_mm)},
                                       {"rotation_rad", Vec(n.rotation_rad)},
                                       {"source", n.source}};
  }
  return j;
}

// The 3D repeatability of carried targets: sqrt(sx^2 + sy^2 + sz^2), pooled over cameras.
double NoiseFloorMm(const WorkcellResult& r, const std::string& camera = "") {
  double sum = 0.0;
  int count = 0;
  for (const auto& [key, n] : r.repeatability.entries) {
    if (key.second == "world") continue;
    if (!camera.empty() && key.first != camera) continue;
    sum += n.position_mm.squaredNorm();
    ++count;
  }
  return count ? std::sqrt(sum / count) : NAN;
}

// " (spread of 3 repeated captures at each of 250 poses)": where NoiseFloorMm's floor came
// from, when every camera's carried targets say the same ("" otherwise).
std::string NoiseFloorSource(const WorkcellResult& r) {
  std::set<std::string> sources;
  for (const auto& [key, n] : r.repeatability.entries) {
    if (key.second != "world") sources.insert(n.source);
  }
  return sources.size() == 1 ? " (" + *sources.begin() + ")" : "";
}

std::vector<double> Vec6(const Eigen::Matrix<double, 6, 1>& v) {
  return {v[0], v[1], v[2], v[3], v[4], v[5]};
}

nlohmann::json EstimateJson(const WorkcellEstimate& e) {
  nlohmann::json j = nlohmann::json::object();
  auto frame = [](const Pose& pose) {
    return nlohmann::json{{"xyz_mm", Vec(pose.t)}, {"rvec_rad", Vec(RvecFromRotation(pose.R))}};
  };
  for (const auto& [robot, pose] : e.T_world_base) j["frames"][robot + ".base"] = frame(pose);
  for (const auto& [target, pose] : e.T_flange_target) j["frames"][target] = frame(pose);
  for (const auto& [camera, pose] : e.T_world_cam) j["frames"][camera] = frame(pose);
  return j;
}

// A number, or null where there is none (an RMS over no points).
nlohmann::json NumberOrNull(double value) {
  return std::isnan(value) ? nlohmann::json(nullptr) : nlohmann::json(value);
}

nlohmann::json ScoreJson(const RecordingScore& v) {
  return {{"recording", v.recording},
          {"before_mm", RmsJson(v.before)},
          {"after_mm", RmsJson(v.after)},
          {"mean_after_mm", v.mean_after_mm},
          {"max_after_mm", v.max_after_mm},
          {"poses", v.poses},
          {"beyond_calibration",
           {{"poses", v.poses_beyond_calibration},
            {"rms_beyond_mm", NumberOrNull(v.rms_beyond_calibration_mm)},
            {"rms_within_mm", NumberOrNull(v.rms_within_calibration_mm)}}}};
}

nlohmann::json BeyondCalibrationJson(const BeyondCalibration& beyond) {
  nlohmann::json joints = nlohmann::json::array();
  for (const JointBeyondCalibration& j : beyond.joints) {
    joints.push_back({{"robot", j.robot},
                      {"joint", j.joint},
                      {"calibration_range_rad", {j.calibration_min_rad, j.calibration_max_rad}},
                      {"scored_range_rad", {j.scored_min_rad, j.scored_max_rad}},
                      {"poses", j.poses}});
  }
  return {{"poses", beyond.poses},
          {"rms_within_mm", NumberOrNull(beyond.rms_within_mm)},
          {"rms_beyond_mm", NumberOrNull(beyond.rms_beyond_mm)},
          {"joints", joints}};
}

nlohmann::json HeldOutSetupJson(const HeldOutSetupScore& v) {
  nlohmann::json points = nlohmann::json::array();
  for (const HeldOutPoint& p : v.points) {
    points.push_back({{"sample", p.sample},
                      {"pose", p.pose},
                      {"camera", p.camera},
                      {"target", p.target},
                      {"error_mm", {p.error_mm.x(), p.error_mm.y(), p.error_mm.z()}},
                      {"sigma_mm", std::sqrt(p.covariance_mm2.trace())},
                      {"normalized_squared", p.normalized_squared},
                      {"beyond_calibration", p.beyond_calibration}});
  }
  return {{"recording", v.recording},
          {"registration_poses", v.registration_poses},
          {"scored_poses", v.scored_poses},
          {"rms_mm", v.rms_mm},
          {"rms_se_mm", v.rms_se_mm},
          {"mean_mm", v.mean_mm},
          {"max_mm", v.max_mm},
          {"registration_rms_mm", v.registration_rms_mm},
          {"nominal_rms_mm", v.nominal_rms_mm},
          {"within_95_ellipsoid", v.within_95},
          {"mean_normalized_squared", v.mean_normalized},
          {"median_sigma_mm", v.median_sigma_mm},
          {"beyond_calibration", BeyondCalibrationJson(v.beyond_calibration)},
          {"points", points}};
}

nlohmann::json WeakJson(const std::vector<WeakParameter>& weak) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& w : weak) {
    j.push_back(
        {{"name", w.name}, {"variance_inflation", w.variance_inflation}, {"partners", w.partners}});
  }
  return j;
}

// A sigma to two significant digits ("0.063", "2.2", "0.00031"): never "0.00" for a small one.
std::string SigmaText(double sigma) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2g", sigma);
  return text;
}

// A value to the decimals its sigma has two significant digits at (at least 5: mm and rad read
// as before), so that a compliance of 7.3e-6 +- 4.2e-7 rad/(N m) does not print as 0.00001.
std::string ValueText(double value, double sigma) {
  int decimals = 5;
  if (std::isfinite(sigma) && sigma > 0.0) {
    decimals = std::clamp(1 - static_cast<int>(std::floor(std::log10(sigma))), 5, 12);
  }
  return FixedNumber(value, decimals);
}

// "sigma parts: statistical (..) mm, systematic between cameras (..) mm, from uncertain inputs
// (..) mm" for a frame's translation, the parts that are there; nothing when only the first is.
void PrintSigmaParts(const FrameEstimate& f, std::ostream& out) {
  auto xyz = [](const Eigen::Matrix<double, 6, 1>& v) {
    return "(" + SigmaText(v[0]) + ", " + SigmaText(v[1]) + ", " + SigmaText(v[2]) + ") mm";
  };
  const bool systematic = f.sigma_systematic.head<3>().maxCoeff() > 0;
  const bool inputs = f.sigma_inputs.head<3>().maxCoeff() > 0;
  if (!systematic && !inputs) return;
  out << "    sigma parts: statistical " << xyz(f.sigma_statistical);
  if (systematic) out << ", systematic between cameras " << xyz(f.sigma_systematic);
  if (inputs) out << ", from uncertain inputs " << xyz(f.sigma_inputs);
  out << "\n";
}

// "T_<a>_<b>": the key of robot b's base in robot a's base.
std::string PairKey(const FrameEstimate& f) {
  auto robot = [](const std::string& base) { return base.substr(0, base.size() - 5); };
  return "T_" + robot(f.parent) + "_" + robot(f.name);
}

// "  ur3.base in ur5e.base: xyz = (..) mm +- (..), rvec = (..) rad +- (..)"
std::string PairSummaryLine(const FrameEstimate& f) {
  const Eigen::Vector3d rvec = RvecFromRotation(f.pose.R);
  auto three = [](const Eigen::Vector3d& v, int digits) {
    return "(" + FixedNumber(v.x(), digits) + ", " + FixedNumber(v.y(), digits) + ", " +
           FixedNumber(v.z(), digits) + ")";
  };
  auto sigmas = [](const Eigen::Vector3d& v) {
    return "(" + SigmaText(v.x()) + ", " + SigmaText(v.y()) + ", " + SigmaText(v.z()) + ")";
  };
  return "  " + f.name + " in " + f.parent + ": xyz = " + three(f.pose.t, 2) + " mm +- " +
         sigmas(f.sigma_mm) + ", rvec = " + three(rvec, 4) + " rad +- " + sigmas(f.sigma_rad) +
         "\n";
}

// "time: start 0.01 s, solve 0.42 s, ... = 1.3 s; peak memory 371 MB". The passes that
// identify again without outliers add to their stage's time (result.json keeps them apart).
std::string StagesLine(const std::vector<StageTime>& stages) {
  std::vector<std::pair<std::string, double>> seconds;  // in the order stages first ran
  double total_s = 0.0, peak_mb = 0.0;
  int passes = 1;
  for (const StageTime& stage : stages) {
    passes = std::max(passes, stage.pass + 1);
    auto it = std::find_if(seconds.begin(), seconds.end(),
                           [&](const auto& entry) { return entry.first == stage.stage; });
    if (it == seconds.end()) it = seconds.insert(seconds.end(), {stage.stage, 0.0});
    it->second += stage.seconds;
    total_s += stage.seconds;
    peak_mb = std::max(peak_mb, stage.peak_resident_mb);
  }
  std::ostringstream out;
  out << "time:";
  for (size_t i = 0; i < seconds.size(); ++i) {
    out << (i ? ", " : " ") << seconds[i].first << " " << FixedNumber(seconds[i].second, 2) << " s";
  }
  out << " = " << FixedNumber(total_s, 2) << " s";
  if (passes > 1) out << " over " << passes << " passes (outliers left out)";
  if (peak_mb > 0) out << "; peak memory " << FixedNumber(peak_mb, 0) << " MB";
  return out.str();
}

}  // namespace

std::string WorkcellResultYaml(const WorkcellResult& result) {
  YAML::Emitter out;
  out << YAML::Comment("cellmetry workcell identification (" +
                       CameraModelName(result.camera_model) + ", " + result.solver.solver +
                       "); lengths mm, angles rad");
  out << YAML::BeginMap << YAML::Key << "frames" << YAML::Value << YAML::BeginMap;
  for (const auto& f : result.frames) EmitFrameYaml(out, f.name, f);
  out << YAML::EndMap;
  if (!result.robot_to_robot.empty()) {  // first order, with the bases' cross-covariance
    out << YAML::Key << "robot_to_robot" << YAML::Value << YAML::BeginMap;
    for (const auto& p : result.robot_to_robot) EmitFrameYaml(out, PairKey(p.frame), p.frame);
    out << YAML::EndMap;
  }
  if (!result.model_parameters.empty()) {
    out << YAML::Key << "model" << YAML::Value << YAML::BeginMap;
    for (const auto& p : result.model_parameters) {
      out << YAML::Key << p.name << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
          << "value" << YAML::Value << p.value << YAML::Key << "sigma" << YAML::Value;
      if (p.held) {
        out << "held";
      } else {
        out << p.sigma;
      }
      out << YAML::Key << "unit" << YAML::Value << p.unit << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

namespace {

nlohmann::json FrameJson(const FrameEstimate& f) {
  nlohmann::json held = nlohmann::json::array();
  nlohmann::json undetermined = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) {
    if (f.held[i]) held.push_back(kFrameParameterNames[i]);
    if (f.undetermined[i]) undetermined.push_back(kFrameParameterNames[i]);
  }
  return {{"parent", f.parent},
          {"xyz_mm", Vec(f.pose.t)},
          {"rvec_rad", Vec(RvecFromRotation(f.pose.R))},
          {"sigma_xyz_mm", SigmaJson(f.sigma_mm, f.held, 0)},
          {"sigma_rot_rad", SigmaJson(f.sigma_rad, f.held, 3)},
          {"sigma_statistical", Vec6(f.sigma_statistical)},
          {"sigma_systematic", Vec6(f.sigma_systematic)},
          {"sigma_inputs", Vec6(f.sigma_inputs)},
          {"held", held},
          {"undetermined", undetermined}};
}

// Each camera left out against the cell with all (camera_left_out.h).
nlohmann::json CamerasLeftOutJson(const std::vector<CameraLeftOut>& cameras) {
  nlohmann::json out = nlohmann::json::array();
  for (const CameraLeftOut& c : cameras) {
    nlohmann::json frames = nlohmann::json::object();
    for (const FrameDifference& d : c.frames) {
      nlohmann::json difference = nlohmann::json::array(), sigma = nlohmann::json::array();
      for (int i = 0; i < 6; ++i) {
        difference.push_back(d.compared[i] ? nlohmann::json(d.difference[i]) : nullptr);
        sigma.push_back(d.compared[i] ? nlohmann::json(d.sigma[i]) : nullptr);
      }
      frames[d.frame] = {{"difference", difference}, {"sigma", sigma}};
    }
    out.push_back({{"camera", c.camera},
                   {"frames", frames},
                   {"worst_sigmas", c.worst_sigmas},
                   {"worst", c.worst},
                   {"flag_sigmas", c.flag_sigmas},
                   {"flagged", c.flagged()},
                   {"error", c.error}});
  }
  return out;
}

nlohmann::json RobotPairJson(const RobotPairEstimate& p) {
  nlohmann::json covariance = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (int k = 0; k < 6; ++k) row.push_back(p.covariance(i, k));
    covariance.push_back(row);
  }
  return {{"parent", p.frame.parent},
          {"frame", p.frame.name},
          {"xyz_mm", Vec(p.frame.pose.t)},
          {"rvec_rad", Vec(RvecFromRotation(p.frame.pose.R))},
          {"sigma_xyz_mm", Vec(p.frame.sigma_mm)},
          {"sigma_rot_rad", Vec(p.frame.sigma_rad)},
          {"covariance", covariance},
          {"sigma_from",
           "first-order propagation of both bases' joint covariance (x y z mm, "
           "rx ry rz rad about the parent's axes)"}};
}

// A held parameter's sigma is null: held, not known perfectly.
nlohmann::json ModelParameterJson(const ScalarEstimate& p) {
  return {{"name", p.name},
          {"unit", p.unit},
          {"nominal", p.nominal},
          {"value", p.value},
          {"sigma", p.held ? nlohmann::json(nullptr) : nlohmann::json(p.sigma)},
          {"sigma_statistical", p.sigma_statistical},
          {"sigma_systematic", p.sigma_systematic},
          {"sigma_inputs", p.sigma_inputs},
          {"held", p.held},
          {"undetermined", p.undetermined},
          {"convention",
           p.convention.empty() ? nlohmann::json(nullptr) : nlohmann::json(p.convention)}};
}

nlohmann::json RobotModelJson(const RobotModelRecord& record) {
  nlohmann::json values = nlohmann::json::array();
  for (const auto& p : record.parameters) {
    values.push_back(
        {{"name", p.name}, {"unit", p.unit}, {"value", p.nominal}, {"free", !p.fixed}});
  }
  nlohmann::json robot = {{"model_file", record.config_file},
                          {"model_config", record.config_text},
                          {"model_values", values}};
  if (!record.joint_ranges_rad.empty()) {
    nlohmann::json ranges = nlohmann::json::array();
    for (const auto& [min_rad, max_rad] : record.joint_ranges_rad) {
      ranges.push_back({min_rad, max_rad});
    }
    robot["joint_ranges_rad"] = ranges;
  }
  return robot;
}

nlohmann::json OutlierJson(const Outlier& o) {
  return {{"line", o.line}, {"sample", o.sample}, {"camera", o.camera},      {"target", o.target},
          {"kind", o.kind}, {"score", o.score},   {"threshold", o.threshold}};
}

// The second pass's stages named as docs/formats.md says.
nlohmann::json StagesJson(const std::vector<StageTime>& stages) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& stage : stages) {
    const std::string name = stage.pass > 0 ? "again_without_outliers/" + stage.stage : stage.stage;
    j.push_back({{"stage", name},
                 {"seconds", stage.seconds},
                 {"peak_resident_mb", stage.peak_resident_mb}});
  }
  return j;
}

}  // namespace

nlohmann::json WorkcellResultJson(const WorkcellResult& r) {
  nlohmann::json j;
  j["format"] = "cellmetry-result/1";
  j["camera_model"] = CameraModelName(r.camera_model);
  j["residual"] = ResidualFormName(r.residual_form);
  j["solver"] = SolverJson(r.solver);
  j["start"] = EstimateJson(r.start);
  for (const auto& f : r.frames) j["frames"][f.name] = FrameJson(f);
  for (const auto& p : r.robot_to_robot) j["robot_to_robot"][PairKey(p.frame)] = RobotPairJson(p);
  j["model_parameters"] = nlohmann::json::array();
  for (const auto& p : r.model_parameters) j["model_parameters"].push_back(ModelParameterJson(p));
  for (const auto& record : r.robot_models) j["robots"][record.robot] = RobotModelJson(record);
  j["effects"] = nlohmann::json::object();
  for (const auto& record : r.effect_models) {
    j["effects"][record.name] = {{"robot", record.robot},
                                 {"type", record.type},
                                 {"stage", record.stage},
                                 {"config", record.config}};
  }
  j["gravity_base_m_s2"] = Vec(r.gravity_base);
  AddUncertaintyJson(r.uncertainty, r.unidentifiable, r.strong_correlations, &j);
  j["weakly_identified"] = WeakJson(r.weakly_identified);
  j["outliers"] = nlohmann::json::array();
  for (const auto& o : r.outliers) j["outliers"].push_back(OutlierJson(o));
  j["noise_used"] = NoiseJson(r.noise);
  j["repeatability"] = NoiseJson(r.repeatability);
  for (const auto& [key, rms] : r.position_rms)
    j["residual_rms"]["position_mm"][key] = RmsJson(rms);
  for (const auto& [key, rms] : r.rotation_rms)
    j["residual_rms"]["rotation_rad"][key] = RmsJson(rms);
  j["held_out"] = HeldOutJson(r.held_out);
  for (const auto& [model, h] : r.other_models) {
    nlohmann::json& other = j["other_models"][model] = HeldOutJson(h);
    const HeldOutGain against_this = CompareHeldOut(h, r.held_out);
    other["difference_mm"] = against_this.gain_mm;
    other["difference_se_mm"] = against_this.standard_error_mm;
    other["difference_paired"] = against_this.paired;
  }
  j["cameras_left_out"] = CamerasLeftOutJson(r.cameras_left_out);
  j["unused_cameras"] = r.unused_cameras;
  j["undetermined"] = nlohmann::json::array();
  for (const auto& f : r.frames) {
    for (int i = 0; i < 6; ++i) {
      if (f.undetermined[i]) j["undetermined"].push_back(f.name + "." + kFrameParameterNames[i]);
    }
  }
  for (const auto& p : r.model_parameters) {
    if (p.undetermined) j["undetermined"].push_back(p.name);
  }
  if (r.validation) j["validation"] = ScoreJson(*r.validation);
  if (r.held_out_setup) j["validation"]["held_out_setup"] = HeldOutSetupJson(*r.held_out_setup);
  const double floor = NoiseFloorMm(r);
  j["noise_floor_mm"] = std::isnan(floor) ? nlohmann::json(nullptr) : nlohmann::json(floor);
  j["skipped_observations"] = r.skipped;
  j["warnings"] = r.warnings;
  j["stages"] = StagesJson(r.stages);
  return j;
}

std::string WorkcellResidualsCsv(const WorkcellResult& result) {
  std::ostringstream out;
  out << "observation,sample,pose,camera,target,kind,ex,ey,ez,nx,ny,nz\n";
  out.precision(9);
  for (const auto& row : result.residuals) {
    out << row.observation << "," << row.sample << "," << row.pose << "," << row.camera << ","
        << row.target << "," << ResidualKindName(row.kind) << "," << row.error.x() << ","
        << row.error.y() << "," << row.error.z() << "," << row.normalized.x() << ","
        << row.normalized.y() << "," << row.normalized.z() << "\n";
  }
  return out.str();
}

void WriteWorkcellResult(const WorkcellResult& result, const std::string& folder,
                         const std::function<void(const std::string& staging)>& extra) {
  StagedDirectory out(folder, "result");
  AtomicWriteFile(out.File("result.yaml"), WorkcellResultYaml(result));
  AtomicWriteFile(out.File("result.json"), WorkcellResultJson(result).dump(2) + "\n");
  AtomicWriteFile(out.File("residuals.csv"), WorkcellResidualsCsv(result));
  AtomicWriteFile(out.File("outliers.csv"), OutliersCsv(result.outliers));
  if (extra) extra(out.staging());
  out.Commit();
}

namespace {

// A frame's line: its pose in its parent, with sigma per coordinate ("held" where it was), and
// the parts of sigma below it.
void PrintFrame(const FrameEstimate& f, std::ostringstream& out) {
  const Eigen::Vector3d rvec = RvecFromRotation(f.pose.R);
  auto sigmas = [&f](const Eigen::Vector3d& sigma, int offset) {
    std::string text;
    for (int i = 0; i < 3; ++i) {
      text += (i ? ", " : "") + (f.held[offset + i]           ? std::string("held")
                                 : f.undetermined[offset + i] ? std::string("undetermined")
                                                              : SigmaText(sigma[i]));
    }
    return "(" + text + ")";
  };
  out << "  " << f.name << " in " << f.parent << ": xyz = (" << FixedNumber(f.pose.t.x(), 2) << ", "
      << FixedNumber(f.pose.t.y(), 2) << ", " << FixedNumber(f.pose.t.z(), 2) << ") mm +- "
      << sigmas(f.sigma_mm, 0) << ", rvec = (" << FixedNumber(rvec.x(), 4) << ", "
      << FixedNumber(rvec.y(), 4) << ", " << FixedNumber(rvec.z(), 4) << ") rad +- "
      << sigmas(f.sigma_rad, 3) << "\n";
  PrintSigmaParts(f, out);
}

// Each pair of robots once, in the job's order; in a large cell the first ten.
void PrintRobotToRobot(const WorkcellResult& r, std::ostringstream& out) {
  if (r.robot_to_robot.empty()) return;
  out << "  robot to robot (sigma from both bases' joint covariance; the reverse ones in "
         "result.yaml):\n";
  std::set<std::pair<std::string, std::string>> said;
  size_t left = 0;
  for (const auto& p : r.robot_to_robot) {
    if (said.count({p.frame.name, p.frame.parent})) continue;
    said.insert({p.frame.parent, p.frame.name});
    if (said.size() > 10) {  // the rest in the files
      ++left;
      continue;
    }
    out << "  " << PairSummaryLine(p.frame);
  }
  if (left > 0) out << "    ... and " << left << " more pairs in result.yaml\n";
}

// What the data could not determine, and what decided it instead.
std::string UnidentifiableLine(const UnidentifiableParameter& u) {
  std::string partners;
  for (const auto& p : u.moves_with) partners += (partners.empty() ? "" : ", ") + p.name;
  if (u.prior_sigma > 0.0) {
    return "not determined by this data: " + u.name + ", taken as 0 +- " +
           SigmaText(u.prior_sigma) + " (its plausible size as a 2-sigma prior); " +
           (partners.empty() ? std::string("it moves nothing else")
                             : "it moves " + partners + ", whose sigma carries it");
  }
  if (!u.convention.empty()) {
    return "held at nominal by convention: " + u.name + " (" + u.convention + ")" +
           (partners.empty() ? std::string() : "; " + partners + " are given relative to it");
  }
  if (u.moves_with.empty()) {
    return "not identifiable, held at nominal: " + u.name + " (" + u.reason + ")";
  }
  return "not identifiable, held at nominal: " + u.name + " (" + u.reason + "): " + partners +
         " are not determined by this data either (marked undetermined; their sigma leaves the "
         "hold out): measure one of them and hold it there, or record what separates them";
}

// The cell without each camera against the cell with all (camera_left_out.h).
void PrintCamerasLeftOut(const WorkcellResult& r, std::ostringstream& out) {
  if (r.cameras_left_out.empty()) return;
  out << "  each camera left out (without it - with all, +- the difference's sigma):\n";
  for (const CameraLeftOut& c : r.cameras_left_out) {
    if (!c.error.empty()) {
      out << "    without " << c.camera << ": not identifiable (" << c.error << ")\n";
      continue;
    }
    out << "    without " << c.camera << ": largest " << FixedNumber(c.worst_sigmas, 1)
        << " sigma (" << (c.worst.empty() ? std::string("none") : c.worst) << ")"
        << (c.flagged() ? " FLAGGED (beyond " + FixedNumber(c.flag_sigmas, 1) + ")" : "") << "\n";
    for (const FrameDifference& d : c.frames) {
      std::string text;
      for (int i = 0; i < 3; ++i) {
        text += (i ? ", " : "") +
                (d.compared[i] ? FixedNumber(d.difference[i], 2) + " +- " + SigmaText(d.sigma[i])
                               : std::string("held"));
      }
      out << "      " << d.frame << " xyz (" << text << ") mm\n";
    }
  }
}

// The model's parameters, the observations left out, what was held and what moves together.
void PrintParameters(const WorkcellResult& r, std::ostringstream& out) {
  for (const auto& p : r.model_parameters) {
    out << "  " << p.name << " = " << ValueText(p.value, p.sigma) << " "
        << (p.held && !p.convention.empty() ? "held (convention)"
            : p.held                        ? "held (not identifiable)"
            : p.undetermined                ? std::string("undetermined")
                                            : "+- " + SigmaText(p.sigma))
        << " " << p.unit << "\n";
  }
  if (!r.outliers.empty()) {
    std::set<std::tuple<int, int, std::string, std::string>> observations;
    for (const auto& o : r.outliers) observations.insert({o.line, o.sample, o.camera, o.target});
    out << "  outliers: " << observations.size()
        << " observations failed the outlier test and were left out (outliers.csv)\n";
  }
  for (const auto& u : r.unidentifiable) out << "  " << UnidentifiableLine(u) << "\n";
  // The five strongest (they come strongest first); the rest are in result.json and the report.
  constexpr size_t kShownCorrelations = 5;
  for (size_t k = 0; k < r.strong_correlations.size() && k < kShownCorrelations; ++k) {
    const CorrelatedPair& c = r.strong_correlations[k];
    out << "  strongly correlated: " << c.a << " ~ " << c.b << " (" << FixedNumber(c.correlation, 3)
        << ")\n";
  }
  if (r.strong_correlations.size() > kShownCorrelations) {
    out << "  strongly correlated: " << r.strong_correlations.size() - kShownCorrelations
        << " more pairs (result.json, report.html)\n";
  }
}

// How well the answer fits: residual RMS per camera and target, held out against the floor,
// and on fresh poses where the job scored some.
void PrintFitQuality(const WorkcellResult& r, std::ostringstream& out) {
  for (const auto& [key, rms] : r.position_rms) {
    out << "  residual RMS " << key << ": x " << FixedNumber(rms.axis.x(), 3) << ", y "
        << FixedNumber(rms.axis.y(), 3) << ", depth " << FixedNumber(rms.axis.z(), 3)
        << " mm (n=" << rms.count << ")\n";
  }
  if (r.held_out.folds > 0) {
    out << "  held-out RMS (" << r.held_out.folds
        << "-fold by pose): " << FixedNumber(r.held_out.total.norm, 3) << " +- "
        << FixedNumber(r.held_out.total_se_mm, 3) << " mm";
    for (const auto& [model, h] : r.other_models) {
      const HeldOutGain against_this = CompareHeldOut(h, r.held_out);
      out << "; " << model << " model: " << FixedNumber(h.total.norm, 3) << " mm ("
          << FixedNumber(std::abs(against_this.gain_mm), 3) << " +- "
          << FixedNumber(against_this.standard_error_mm, 3) << " mm "
          << (against_this.gain_mm >= 0 ? "worse" : "better")
          << (against_this.paired ? ", paired" : "") << ")";
    }
    const double floor = NoiseFloorMm(r);
    out << "; noise floor "
        << (std::isnan(floor) ? std::string("unknown (no repeated captures)")
                              : FixedNumber(floor, 3) + " mm")
        << NoiseFloorSource(r) << "\n";
  }
  if (r.validation) {
    const RecordingScore& v = *r.validation;
    out << "  on fresh poses (" << v.after.count << " from " << v.recording << "): RMS before "
        << FixedNumber(v.before.norm, 3) << " mm (closed-form start), after "
        << FixedNumber(v.after.norm, 4) << " mm; mean " << FixedNumber(v.mean_after_mm, 4)
        << ", max " << FixedNumber(v.max_after_mm, 4) << " mm\n";
    const std::string beyond = BeyondCalibrationText(v);
    if (!beyond.empty()) out << "    " << beyond << "\n";
  }
  if (r.held_out_setup) {
    const HeldOutSetupScore& v = *r.held_out_setup;
    out << "  held-out setup (" << v.recording << "): frames registered again on "
        << v.registration_poses.size() << " poses (RMS " << FixedNumber(v.registration_rms_mm, 4)
        << " mm), " << v.scored_poses << " scored: RMS " << FixedNumber(v.rms_mm, 4) << " +- "
        << FixedNumber(v.rms_se_mm, 4) << " mm (nominal model " << FixedNumber(v.nominal_rms_mm, 4)
        << " mm), mean " << FixedNumber(v.mean_mm, 4) << ", max " << FixedNumber(v.max_mm, 4)
        << " mm; predicted sigma " << FixedNumber(v.median_sigma_mm, 4) << " mm (median), "
        << FixedNumber(100.0 * v.within_95, 1) << " % within their 95 % ellipsoid\n";
    const std::string beyond = BeyondCalibrationText(v);
    if (!beyond.empty()) out << "    " << beyond << "\n";
  }
}

}  // namespace

std::string WorkcellSummary(const WorkcellResult& r) {
  std::ostringstream out;
  out << "Workcell identification (" << CameraModelName(r.camera_model)
      << (r.residual_form == ResidualForm::kJointSpace ? ", joint-space residual" : "")
      << ", solver " << r.solver.solver << ": " << r.solver.iterations << " iterations, "
      << FixedNumber(r.solver.time_s * 1e3, 1) << " ms, " << r.solver.stop_reason << ")\n";
  for (const auto& f : r.frames) PrintFrame(f, out);
  PrintRobotToRobot(r, out);
  PrintParameters(r, out);
  PrintFitQuality(r, out);
  PrintCamerasLeftOut(r, out);
  for (const auto& w : r.warnings) out << "  warning: " << w << "\n";
  if (!r.stages.empty()) out << "  " << StagesLine(r.stages) << "\n";
  return out.str();
}

}  // namespace cellmetry
