// Reading a homing job (homing_job.h) on top of the one job reader.
#include "cellmetry/cell/homing_job.h"

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

void Require(bool ok, const std::string& file, const std::string& what, const std::string& hint) {
  if (!ok) throw InputError({file, 0, 0}, what, hint);
}

HomingOptions ReadOptions(const ConfigNode& h) {
  HomingOptions options;
  h.ExpectKeys({"n_sigma", "target_width_increments", "min_positions", "max_reruns"});
  options.n_sigma = h.GetDoubleIn("n_sigma", options.n_sigma, 1e-3, 100.0,
                                  "How many sigma an interval spans: 3 is usual");
  options.target_width_increments =
      h.GetDoubleIn("target_width_increments", options.target_width_increments, 1e-6, 1e6,
                    "A width in encoder increments, more than 0");
  options.min_positions = h.GetIntIn("min_positions", options.min_positions, 2, 1000000,
                                     "An interval needs company: 2 or more");
  options.max_reruns = h.GetIntIn("max_reruns", options.max_reruns, 0, 1000,
                                  "0 runs once; each rerun records the poses again");
  return options;
}

}  // namespace

HomingJob LoadHomingJob(const std::string& path, Registry& registry) {
  HomingJob h;
  h.job = LoadWorkcellJob(path, registry);
  const WorkcellProblem& p = h.job.problem;
  Require(h.job.kind == "homing", path, "not a homing job (job: " + h.job.kind + ")",
          "Run workcell jobs with 'cellmetry run'");
  Require(p.world_target.empty() && p.robots.size() == 1 && p.robots[0].tools.size() == 1, path,
          "homing takes one robot with one marker and no world target",
          "Write world_target: none and one robot with its marker under tools:");
  const WorkcellRobot& robot = p.robots[0];
  Require(robot.model->has_inverse(), robot.model_file,
          "homing needs a robot model with inverse kinematics", "Use a delta arm config");
  Require(p.cameras.size() == 1 && p.cameras.begin()->second.start.has_value(), path,
          "homing needs the one camera's calibrated pose",
          "Give cameras: {<name>: {xyz: [mm], rvec: [rad]}} from a calibration result");
  const auto sigma = p.noise.position_sigma_mm.find(p.cameras.begin()->first);
  Require(sigma != p.noise.position_sigma_mm.end(), path, "homing needs the camera's noise",
          "Give noise: {cameras: {<name>: {position_mm: [x, y, depth]}}}");
  h.robot = robot.name;
  h.camera = p.cameras.begin()->first;
  h.target = robot.tools[0].target;
  h.arm.model = robot.model;
  h.arm.model_parameters = robot.model_parameters;
  h.arm.T_base_cam = *p.cameras.begin()->second.start;  // the world is the base here
  h.arm.marker_mm = robot.tools[0].flange_tool.start.t;
  h.sigma_mm = sigma->second;
  if (h.job.homing) h.options = ReadOptions(*h.job.homing);
  return h;
}

std::vector<PointSample> CollectPoints(const HomingJob& job, const Recording& recording) {
  ValidateJobAgainstRecording(job.job, recording);
  std::vector<PointSample> points;
  for (const Observation& obs : recording.observations) {
    if (obs.target != job.target || obs.camera != job.camera) continue;
    const Sample& sample = recording.samples[recording.SampleIndex(obs.sample)];
    points.push_back({sample.id,
                      sample.q,
                      obs.position_mm,
                      {recording.folder + "/samples.csv", sample.line, 0},
                      {recording.folder + "/observations.csv", obs.line, 0}});
  }
  if (points.empty()) {
    throw InputError({recording.folder + "/observations.csv", 0, 0},
                     "no observation of target '" + job.target + "' by camera '" + job.camera + "'",
                     "Record the marker with that camera, or name the ones the observations use");
  }
  return points;
}

}  // namespace cellmetry
