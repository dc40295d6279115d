// `cellmetry run` for `job: kinematic`: calibrate, score on fresh positions if given, write.
#include <cstdio>

#include "cellmetry/cell/kinematic_calibration.h"
#include "cellmetry/cell/kinematic_job.h"
#include "cellmetry/cell/kinematic_result_io.h"
#include "cellmetry/basics/progress.h"
#include "commands.h"

namespace cellmetry::app {
namespace {

// Prediction - measurement on the validation recording, before (nominal model, closed-form
// camera) and after calibration.
KinematicValidation Validate(const KinematicJob& job, const KinematicResult& result) {
  KinematicValidation v;
  v.recording = *job.validation_recording;
  const std::vector<PointSample> fresh =
      CollectPointSamples(job.problem, ReadRecording(*job.validation_recording));
  KinematicState before;
  before.T_base_cam = result.closed_form_camera.T_base_cam;
  before.marker_mm = job.problem.marker_mm;
  for (const auto& p : job.problem.model_parameters) before.model_values.push_back(p.nominal);
  v.before = RmsOf(PredictionErrors(*job.problem.model, before, fresh));
  const std::vector<Eigen::Vector3d> after = PredictionErrors(*job.problem.model, result.state, fresh);
  v.after = RmsOf(after);
  for (const auto& e : after) {
    v.mean_after_mm += e.norm() / after.size();
    v.max_after_mm = std::max(v.max_after_mm, e.norm());
  }
  return v;
}

}  // namespace

void RunKinematicJob(const std::string& job_path, const std::string& output) {
  Registry& registry = Registry::Global();
  const KinematicJob job = LoadKinematicJob(job_path, registry);
  const std::vector<PointSample> samples =
      CollectPointSamples(job.problem, ReadRecording(job.recording));
  Progress::Note("calibrating on " + std::to_string(samples.size()) + " measured positions (" +
                 FormulationName(job.problem.formulation) + " formulation)");
  const SolverMaker make_solver = [&] {
    return registry.CreateSolver(job.solver_type, *job.solver_config);
  };
  const KinematicResult result = CalibrateKinematics(job.problem, samples, make_solver);
  std::optional<KinematicValidation> validation;
  if (job.validation_recording) validation = Validate(job, result);
  const std::string folder = output.empty() ? job.output : output;
  WriteKinematicResult(job.problem, result, samples, validation, folder);
  std::printf("%s", KinematicSummary(result, validation).c_str());
  std::printf("  written: %s/{result.yaml,result.json,residuals.csv}\n", folder.c_str());
}

}  // namespace cellmetry::app
