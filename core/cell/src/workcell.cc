// The workcell identification (workcell.h): fit, sigma, uncertainty, residuals, held-out.
#include "cellmetry/cell/workcell.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <mutex>
#include <random>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/basics/stage_clock.h"
#include "cellmetry/cell/outliers.h"
#include "cellmetry/cell/robot_pairs.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/reweighted_solve.h"
#include "camera_left_out_fit.h"
#include "far_start.h"
#include "fit_once.h"
#include "input_link_schedule.h"
#include "input_uncertainty.h"
#include "residual_rows.h"
#include "robust_first_fit.h"
#include "uncertainty_split.h"
#include "workcell_description.h"
#include "workcell_warnings.h"

namespace cellmetry {

Fit FitOnce(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
            const NoiseModel& noise, const WorkcellEstimate& start, const std::set<int>& poses,
            HeldParameters held, const SolverMaker& make_solver, bool warm_start) {
  Fit fit;
  fit.assembled = AssembleWorkcell(spec, recording, data, noise, start, poses);
  fit.free_as_asked = fit.assembled->problem.num_free();
  IdentifiedSolve solved =
      SolveHoldingUnidentifiable(&fit.assembled->problem, spec.identifiability_tolerance,
                                 std::move(held), make_solver, warm_start);
  fit.summary = solved.summary;
  fit.unidentifiable = std::move(solved.unidentifiable);
  fit.at_answer = std::move(solved.at_answer);
  return fit;
}

SolverMaker FirstFitSolver(const NoiseModel& noise, const SolverMaker& job_solver) {
  if (!noise.has_unknown()) return job_solver;
  ReweightedSolveOptions options;
  options.decrement_tolerance = 1e-10;
  return ReweightedSolver(options);
}

namespace {

// A row that measures a robot: a target it carries, or the world target as a camera riding on
// it sees it (eye in hand).
bool MeasuresARobot(const Recording& recording, const ResidualRow& row) {
  return recording.IsCarried(row.target) || recording.camera_mounts.count(row.camera) > 0;
}

// Prediction - measurement rows at `estimate`, in the measurement's units (mm / rad), whatever
// residual form the fit used: a joint-space fit's rows are whitened joint errors, so its
// measurements are compared again in the camera frame.
std::vector<ResidualRow> MeasurementRows(const WorkcellProblem& spec, const Recording& recording,
                                         const WorkcellData& data, const NoiseModel& noise,
                                         const WorkcellEstimate& estimate,
                                         const std::set<int>& poses, AssembledWorkcell* fitted,
                                         const Linearization* at = nullptr) {
  if (spec.residual == ResidualForm::kCartesian && fitted) return ResidualRows(*fitted, at);
  WorkcellProblem cartesian = spec;
  cartesian.residual = ResidualForm::kCartesian;
  auto assembled = AssembleWorkcell(cartesian, recording, data, noise, estimate, poses);
  return ResidualRows(*assembled);
}

// Replaces "unknown" sigma by the residual RMS per axis, corrected for the fitted parameters.
bool EstimateUnknownSigma(const std::vector<ResidualRow>& rows, int num_free, NoiseModel* noise) {
  std::map<NoiseKey, std::pair<ResidualRms, ResidualRms>> sums;  // position, rotation
  int total_rows = 0;
  for (const auto& row : rows) {
    auto& entry = sums[{row.camera, row.target}];
    (row.kind == ResidualKind::kPosition ? entry.first : entry.second).Add(row.error);
    total_rows += 3;
  }
  const double dof_correction =
      total_rows > num_free ? std::sqrt(double(total_rows) / (total_rows - num_free)) : 1.0;
  bool changed = false;
  for (auto& [key, target_noise] : noise->entries) {
    if (target_noise.source != "unknown" || !sums.count(key)) continue;
    auto& [position, rotation] = sums[key];
    position.Finish();
    rotation.Finish();
    if (position.count > 0) {
      // Rows that carry their own covariance: sigma is what is left beside it.
      const Eigen::Vector3d scatter_mm2 = (position.axis * dof_correction).cwiseAbs2();
      target_noise.position_mm =
          (scatter_mm2 - target_noise.mean_row_variance_mm2).cwiseMax(1e-12).cwiseSqrt();
    }
    if (rotation.count > 0) {
      target_noise.rotation_rad = (rotation.axis * dof_correction).cwiseMax(1e-9);
    }
    target_noise.source = target_noise.per_row
                              ? "residuals of a first fit, beside each row's own uncertainty"
                              : "residuals of a first fit";
    changed = true;
  }
  return changed;
}

}  // namespace

HeldOut CrossValidate(const WorkcellProblem& spec, const Recording& recording,
                      const WorkcellData& data, const NoiseModel& noise,
                      const WorkcellEstimate& answer, const HeldParameters& held,
                      const SolverMaker& make_solver) {
  HeldOut out;
  std::vector<int> poses;
  for (const auto& m : data.tools) poses.push_back(recording.samples[m.sample_index].pose);
  std::sort(poses.begin(), poses.end());
  poses.erase(std::unique(poses.begin(), poses.end()), poses.end());
  const int folds = std::min<int>(spec.folds, static_cast<int>(poses.size()));
  if (folds < 2) return out;
  std::mt19937 rng(spec.seed);
  std::shuffle(poses.begin(), poses.end(), rng);
  out.folds = folds;
  // The folds side by side (each fit's own threads leave its serial parts to overlap), then
  // summed in fold order, so that the answer does not depend on which finished first.
  struct FoldRows {
    std::vector<ResidualRow> rows;  // the held-out carried-target rows
  };
  std::vector<FoldRows> fold_rows(folds);
  Progress progress("cross-validation (" + CameraModelName(spec.camera_model) + ") fold", folds);
  std::mutex progress_mutex;
  tbb::parallel_for(0, folds, [&](int f) {
    std::set<int> train, test;
    for (size_t i = 0; i < poses.size(); ++i) {
      (static_cast<int>(i) % folds == f ? test : train).insert(poses[i]);
    }
    Fit fit = FitOnce(spec, recording, data, noise, answer, train, held, make_solver,
                      /*warm_start=*/true);
    const WorkcellEstimate trained = ReadEstimate(spec, *fit.assembled);
    for (auto& row : MeasurementRows(spec, recording, data, noise, trained, test, nullptr)) {
      if (MeasuresARobot(recording, row)) fold_rows[f].rows.push_back(std::move(row));
    }
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress.Advance();
  });
  for (const FoldRows& f : fold_rows) {
    ResidualRms fold;
    double normalized_ss = 0.0;  // every carried-target row the fit uses: rotations too, where
    int normalized_rows = 0;     // an effect may show most (a delta platform's tilt)
    for (const auto& row : f.rows) {
      normalized_ss += row.normalized.squaredNorm();
      normalized_rows += 3;
      if (row.kind != ResidualKind::kPosition) continue;
      out.total.Add(row.error);
      out.per_camera[row.camera].Add(row.error);
      fold.Add(row.error);
    }
    out.per_fold_normalized_rms.push_back(
        normalized_rows > 0 ? std::sqrt(normalized_ss / normalized_rows) : 0.0);
    fold.Finish();
    out.per_fold.push_back(fold);
  }
  out.total.Finish();
  for (auto& [camera, rms] : out.per_camera) rms.Finish();
  return out;
}

std::string CameraModelName(CameraModel model) {
  return model == CameraModel::kStaticCameras ? "static_cameras" : "per_frame";
}

namespace {

// More measured rows than the free parameters the job asked for, or the fit is not a fit (held
// unidentifiable parameters do not count: with too few rows, every direction is one).
void CheckEnoughData(const Recording& recording, const Fit& fit) {
  const int rows = fit.assembled->problem.num_residuals();
  if (rows >= fit.free_as_asked) return;
  throw InputError({recording.folder + "/observations.csv", 0, 0},
                   "the recording gives " + std::to_string(rows) + " measured values for " +
                       std::to_string(fit.free_as_asked) + " free parameters",
                   "Record more poses, or free fewer parameters");
}

// The robust first fit (robust_first_fit.h) with the uncertain inputs' link started at its
// least-squares start, in its LeastSquaresFit's schedule: that fit's answer is the plain fit's
// when nothing is left out (the usual case), so the link is assembled beside the fit's own
// assembly and solve, and linked at that answer alongside the Cauchy step and the test. Not
// where a sigma is unknown: FitWithSigma then solves again with sigma from this fit's
// residuals and links the inputs at that answer, and a link here would only take the other
// core from the fit (sim_b).
RobustFirstFit FindOutliersLinkingInputs(const WorkcellProblem& spec, const Recording& recording,
                                         const SolverMaker& make_solver) {
  RobustFirstFitOptions options;
  options.at_least_squares_start = [&recording](LeastSquaresFit* ls) {
    if (ls->inputs.noise.has_unknown()) return false;
    return ls->input_link.Start(ls->spec, recording, ls->inputs.data, ls->inputs.noise,
                                ls->inputs.start);
  };
  options.at_least_squares_answer = [](LeastSquaresFit* ls) {
    if (ls->input_link.started()) ls->input_link.Answer(AnswerOf(*ls->fit.assembled));
  };
  return FindOutliersByRobustFit(spec, recording, make_solver, options);
}

// The uncertain inputs' link of `fit`, in `input_link`: where neither the refit started it
// (FitWithSigma) nor the robust first fit at this very answer (`solved`, whose link is taken),
// started now at `fit`'s answer, read now, and assembled at the start `fit` was.
void LinkInputsAtTheAnswer(const WorkcellProblem& spec, const Recording& recording,
                           const WorkcellData& data, const NoiseModel& noise, const Fit& fit,
                           LeastSquaresFit* solved, InputLinkSchedule* input_link) {
  if (input_link->started()) return;
  if (solved && solved->input_link.started()) {
    *input_link = std::move(solved->input_link);
    return;
  }
  input_link->Answer(AnswerOf(*fit.assembled));
  input_link->Start(spec, recording, data, noise, ReferenceEstimate(spec, *fit.assembled));
}

// Solves; where sigma is unknown, estimates it from the first fit's residuals and solves again
// (variance component estimation), holding what the first fit found unidentifiable. `solved`:
// that first fit done already (LeastSquaresFit), taken instead of solving. Where it solves
// again, the uncertain inputs' link is started in `input_link` at that refit's start, assembled
// on the other core while the refit solves on the cores left, and answered with the refit's
// answer (`input_link` is left as it is otherwise). `spec`, `recording`, `data` and `noise`
// are what that link reads (input_link_schedule.h).
Fit FitWithSigma(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
                 const WorkcellEstimate& start, const SolverMaker& make_solver,
                 NoiseModel* noise, Fit* solved, InputLinkSchedule* input_link) {
  Fit fit = solved ? std::move(*solved)
                   : FitOnce(spec, recording, data, *noise, start, {}, {},
                             FirstFitSolver(*noise, make_solver));
  CheckEnoughData(recording, fit);
  if (!noise->has_unknown()) return fit;  // every sigma is known: nothing to re-estimate
  const WorkcellEstimate first = ReadEstimate(spec, *fit.assembled);
  const auto rows = MeasurementRows(spec, recording, data, *noise, first, {}, fit.assembled.get(),
                                    &fit.at_answer);
  // Solved again by the job's solver also where no sigma could be estimated (an unknown one
  // with no rows): the first fit's answer was the core's (FirstFitSolver).
  if (EstimateUnknownSigma(rows, fit.assembled->problem.num_free(), noise)) {
    Progress::Note("refitting with sigma estimated from the residuals");
  }
  std::vector<UnidentifiableParameter> held_first = fit.unidentifiable;
  const SolverSummary first_summary = fit.summary;
  // A refit given up before its answer leaves the link unanswered, which ends it
  // (input_link_schedule.h).
  const bool link_beside = input_link->Start(spec, recording, data, *noise, first);
  // Warm: from the first fit's answer with what it held, so the identifiability check before
  // the solve is skipped; a near-degeneracy the new row weights make shows in the check at the
  // answer, which holds it and solves again (SolveHoldingUnidentifiable).
  fit = FitOnce(spec, recording, data, *noise, first, {}, HeldOf(held_first),
                link_beside ? LeavingOneCore(make_solver) : make_solver, /*warm_start=*/true);
  input_link->Answer(AnswerOf(*fit.assembled));
  // One solve in the report: iterations and time add up; the refit keeps the first's findings.
  fit.summary.iterations += first_summary.iterations;
  fit.summary.evaluations += first_summary.evaluations;
  fit.summary.time_s += first_summary.time_s;
  held_first.insert(held_first.end(), fit.unidentifiable.begin(), fit.unidentifiable.end());
  fit.unidentifiable = held_first;
  return fit;
}

// Residual rows and their RMS per camera and target, in the measurement's units.
// `at`: the fit's linearization at its answer, whose residuals are taken (ResidualRows).
void AddResidualStatistics(const WorkcellProblem& spec, const Recording& recording,
                           const WorkcellData& data, const Fit& fit, const Linearization& at,
                           WorkcellResult* result) {
  result->residuals = MeasurementRows(spec, recording, data, result->noise, result->estimate, {},
                                      fit.assembled.get(), &at);
  // Each row's table looked up among the few met so far (a camera and target's positions and
  // rotations): a name made and found in a map per row was half of this on exp_a.
  struct Group {
    const ResidualRow* first;
    ResidualRms* rms;
  };
  std::vector<Group> groups;
  for (const auto& row : result->residuals) {
    ResidualRms* rms = nullptr;
    for (const Group& group : groups) {
      if (group.first->camera == row.camera && group.first->target == row.target &&
          group.first->kind == row.kind) {
        rms = group.rms;
        break;
      }
    }
    if (rms == nullptr) {
      auto& table =
          row.kind == ResidualKind::kPosition ? result->position_rms : result->rotation_rms;
      rms = &table[row.camera + "/" + row.target];
      groups.push_back({&row, rms});
    }
    rms->Add(row.error);
  }
  for (auto& [key, rms] : result->position_rms) rms.Finish();
  for (auto& [key, rms] : result->rotation_rms) rms.Finish();
}

// The held-out RMS of the other camera model (compare_camera_models).
void CompareCameraModels(const WorkcellProblem& spec, const Recording& recording,
                         const SolverMaker& make_solver, WorkcellResult* result) {
  WorkcellProblem other = spec;
  other.compare_camera_models = false;
  other.outlier_test = OutlierTest::kPlain;  // `recording` is already without the robust fit's
  other.camera_model = spec.camera_model == CameraModel::kStaticCameras
                           ? CameraModel::kPerFrame
                           : CameraModel::kStaticCameras;
  Progress::Note("comparing with the " + CameraModelName(other.camera_model) + " model");
  result->other_models[CameraModelName(other.camera_model)] =
      IdentifyWorkcell(other, recording, make_solver).held_out;
}

// The fit's covariance (split into its parts) and its residual statistics. The residual rows
// read the answer's residuals and nothing else the covariance reads or writes: made on another
// core meanwhile (the inputs' link is done by then on exp_a). Without a valid linearization they
// would evaluate the problem: then after the covariance, which throws for it anyway.
void AddCovarianceAndResiduals(const WorkcellProblem& spec, const Recording& recording,
                               const WorkcellData& data, const Fit& fit,
                               const Linearization& at_answer, InputLinkSchedule* input_link,
                               StageClock* clock, WorkcellResult* result) {
  input_link->RunAlongside(
      [&] {
        result->uncertainty = ComputeUncertainty(fit.assembled->problem, at_answer);
        result->strong_correlations = StrongCorrelations(result->uncertainty);
        SplitUncertainty(spec, recording, *fit.assembled, at_answer, &result->uncertainty);
        clock->Lap("covariance");
      },
      [&] { AddResidualStatistics(spec, recording, data, fit, at_answer, result); },
      /*alongside_on_another_core=*/at_answer.valid);
  clock->Lap("residual_statistics");  // what was left of it after the covariance
}

}  // namespace

// One identification on `recording` as it is. `solved`: the robust first fit's least-squares
// fit of this very recording (a Cartesian job), which is the plain fit's first solve: its data,
// noise, start and answer are taken, not made again.
WorkcellResult IdentifyOnce(const WorkcellProblem& spec, const Recording& recording,
                            const SolverMaker& make_solver,
                            std::unique_ptr<LeastSquaresFit> solved = nullptr) {
  WorkcellResult result;
  result.camera_model = spec.camera_model;
  result.residual_form = spec.residual;
  StageClock clock;
  FitInputs prepared;  // `solved`'s residuals point into its own data: that one is used then
  if (!solved) prepared = PrepareFitInputs(spec, recording);
  const FitInputs& inputs = solved ? solved->inputs : prepared;
  const WorkcellData& data = inputs.data;
  result.skipped = data.skipped;
  result.repeatability = inputs.repeatability;
  result.noise = inputs.noise;
  result.start = inputs.start;
  clock.Lap("start");

  Progress::Note("fitting " + std::to_string(data.tools.size()) + " target observations (" +
                 CameraModelName(spec.camera_model) + ", " + ResidualFormName(spec.residual) +
                 " residual)");
  // How the answer leans on the uncertain inputs needs only the answer: worked out on the other
  // core while this one finds the fit's own uncertainty and residuals; where sigma is refitted,
  // assembled during that refit already (FitWithSigma). After what it reads: it goes first.
  InputLinkSchedule input_link;
  Fit fit = FitWithSigma(spec, recording, data, result.start, make_solver, &result.noise,
                         solved ? &solved->fit : nullptr, &input_link);
  result.solver = fit.summary;
  result.unidentifiable = fit.unidentifiable;
  result.estimate = ReadEstimate(spec, *fit.assembled);
  clock.Lap("solve");
  LinkInputsAtTheAnswer(spec, recording, data, result.noise, fit, solved.get(), &input_link);
  // The solve's last identifiability check linearized here already (with its R factor).
  const Linearization at_answer =
      fit.at_answer.valid ? std::move(fit.at_answer) : Linearize(fit.assembled->problem);
  AddCovarianceAndResiduals(spec, recording, data, fit, at_answer, &input_link, &clock, &result);
  AddInputUncertainty(input_link.Take(), &result.uncertainty);  // rethrows what the link threw
  const HeldParameters held = HeldOf(result.unidentifiable);
  DescribeEstimate(spec, held.held, &result);
  AddModelWarnings(spec, &result);
  result.robot_to_robot = RobotToRobot(result);
  clock.Lap("input_uncertainty");
  result.held_out = CrossValidate(spec, recording, data, result.noise, result.estimate, held,
                                  make_solver);
  clock.Lap("cross_validation");
  if (spec.compare_camera_models) {
    CompareCameraModels(spec, recording, make_solver, &result);
    clock.Lap("camera_models");
  }
  AddWarnings(spec, &result);
  AddStillJointWarnings(spec, recording, data, &result);
  result.stages = clock.stages();
  return result;
}

namespace {

// `spec` without the cameras it does not use (what IdentifyWorkcell then fits).
WorkcellProblem WithoutUnusedCameras(const WorkcellProblem& spec) {
  WorkcellProblem out = spec;
  for (auto it = out.cameras.begin(); it != out.cameras.end();) {
    it = it->second.use ? std::next(it) : out.cameras.erase(it);
  }
  return out;
}

// The cell without each camera in turn, against `result` (fitted on `recording`), and a warning
// for each camera whose absence moves a base or a tool beyond its sigma.
void AddCamerasLeftOut(const WorkcellProblem& spec, const Recording& recording,
                       const SolverMaker& make_solver, WorkcellResult* result) {
  if (!spec.leave_one_camera_out) return;
  StageClock clock;
  result->cameras_left_out = LeaveEachCameraOut(spec, recording, *result, make_solver);
  if (result->cameras_left_out.empty()) return;  // fewer than two cameras: nothing was left out
  AddCameraLeftOutWarnings(result);
  clock.Lap("cameras_left_out");
  result->stages.insert(result->stages.end(), clock.stages().begin(), clock.stages().end());
}

}  // namespace

namespace {

// The identification from the job's starts (or the closed form where it gives none).
WorkcellResult IdentifyFromStart(const WorkcellProblem& spec, const Recording& recording,
                                 const SolverMaker& make_solver);
// The identification from the job's far starts and from the closed form's, the better kept.
WorkcellResult BetterOfTwoStarts(const WorkcellProblem& spec, const WorkcellProblem& closed,
                                 const std::vector<FarStart>& far, const Recording& recording,
                                 const SolverMaker& make_solver);

}  // namespace

WorkcellResult IdentifyWorkcell(const WorkcellProblem& spec, const Recording& recording,
                                const SolverMaker& make_solver) {
  const std::set<std::string> unused = UnusedCameras(spec);
  if (!unused.empty()) {
    const Recording used = WithoutCameras(recording, unused);
    WorkcellResult result = IdentifyWorkcell(WithoutUnusedCameras(spec), used, make_solver);
    NumberByOriginal(recording, used, &result.residuals);
    result.unused_cameras.assign(unused.begin(), unused.end());
    return result;
  }
  WorkcellProblem without_starts;
  const std::vector<FarStart> far = FarStarts(spec, recording, &without_starts);
  if (far.empty()) return IdentifyFromStart(spec, recording, make_solver);
  return BetterOfTwoStarts(spec, without_starts, far, recording, make_solver);
}

namespace {

// Both fits, scored by how well each predicts the carried targets of the recording (the same
// rows for both, whatever each left out as outliers): the better kept, the choice a warning.
WorkcellResult BetterOfTwoStarts(const WorkcellProblem& spec, const WorkcellProblem& closed,
                                 const std::vector<FarStart>& far, const Recording& recording,
                                 const SolverMaker& make_solver) {
  Progress::Note("the job's start lies far from the data's closed form: fitting from both");
  std::optional<WorkcellResult> given, own;
  std::string given_failure;
  try {
    given = IdentifyFromStart(spec, recording, make_solver);
  } catch (const InputError& e) {
    given_failure = e.message();
  }
  try {
    own = IdentifyFromStart(closed, recording, make_solver);
  } catch (const InputError&) {
    if (!given) throw;
    return *given;  // the closed form's fit fails where the given start's holds
  }
  const double own_mm = ScoreOnRecording(closed, *own, recording).after.norm;
  std::optional<double> given_mm;
  if (given) given_mm = ScoreOnRecording(spec, *given, recording).after.norm;
  // The same answer to a part in a thousand: the start was far but harmless.
  const bool same = given && std::abs(*given_mm - own_mm) <= 1e-3 * own_mm;
  const bool keep_given = given && *given_mm <= own_mm * (1 + 1e-3);
  WorkcellResult& kept = keep_given ? *given : *own;
  AddFarStartWarning(far, given_mm, given_failure, own_mm, same, keep_given, &kept);
  return kept;
}

WorkcellResult IdentifyFromStart(const WorkcellProblem& spec, const Recording& recording,
                                 const SolverMaker& make_solver) {
  // Gross outliers (outliers.h): those a robust first fit finds are left out before the plain
  // fit; then what the plain fit's own residuals show, left out and the cell identified again,
  // twice at most (what the first ones masked shows in the second pass). Clean data: the plain
  // answer, untouched.
  StageClock clock;
  std::vector<Outlier> outliers;
  std::unique_ptr<LeastSquaresFit> solved;  // the plain fit's first solve, when it is
  if (spec.outlier_test == OutlierTest::kRobust) {
    RobustFirstFit robust = FindOutliersLinkingInputs(spec, recording, make_solver);
    outliers = std::move(robust.outliers);
    if (outliers.empty()) solved = std::move(robust.least_squares);
    clock.Lap("robust_first_fit");
  }
  if (!outliers.empty()) {
    Progress::Note(std::to_string(outliers.size()) + " residual rows of a robust fit fail the "
                   "outlier test; fitting without their observations");
  }
  Recording kept = outliers.empty() ? Recording{} : WithoutOutliers(recording, outliers);
  const Recording& first = outliers.empty() ? recording : kept;
  WorkcellResult result = IdentifyOnce(spec, first, make_solver, std::move(solved));
  result.stages.insert(result.stages.begin(), clock.stages().begin(), clock.stages().end());
  if (outliers.empty()) kept = recording;
  const int passes = spec.outlier_test == OutlierTest::kOff ? 0 : 2;
  for (int pass = 0; pass < passes; ++pass) {
    const std::vector<Outlier> found = FindOutliers(result.residuals, kept);
    if (found.empty()) break;
    Progress::Note(std::to_string(found.size()) + " residual rows fail the outlier test; "
                   "identifying again without their observations");
    outliers.insert(outliers.end(), found.begin(), found.end());
    kept = WithoutOutliers(kept, found);
    std::vector<StageTime> stages = std::move(result.stages);
    result = IdentifyOnce(spec, kept, make_solver);
    for (StageTime& stage : result.stages) stage.pass = pass + 1;
    result.stages.insert(result.stages.begin(), stages.begin(), stages.end());
  }
  result.outliers = outliers;
  AddCamerasLeftOut(spec, kept, make_solver, &result);
  if (!outliers.empty()) NumberByOriginal(recording, kept, &result.residuals);
  return result;
}

}  // namespace

RecordingScore ScoreOnRecording(const WorkcellProblem& spec, const WorkcellResult& result,
                                const Recording& fresh) {
  RecordingScore score;
  score.recording = fresh.folder;
  const WorkcellData data = PrepareWorkcellData(spec, fresh);
  const NoiseModel noise = BuildNoiseModel(fresh, spec.noise);
  WorkcellProblem cartesian = spec;
  cartesian.residual = ResidualForm::kCartesian;
  auto rms_at = [&](const WorkcellEstimate& estimate, double* mean, double* max) {
    ResidualRms rms;
    const auto rows = ResidualRows(*AssembleWorkcell(cartesian, fresh, data, noise, estimate));
    int count = 0;
    for (const auto& row : rows) {
      if (row.kind != ResidualKind::kPosition || !MeasuresARobot(fresh, row)) continue;
      rms.Add(row.error);
      if (mean) *mean += row.error.norm();
      if (max) *max = std::max(*max, row.error.norm());
      ++count;
    }
    if (mean && count > 0) *mean /= count;
    rms.Finish();
    return rms;
  };
  score.before = rms_at(result.start, nullptr, nullptr);
  score.after = rms_at(result.estimate, &score.mean_after_mm, &score.max_after_mm);
  return score;
}

std::string ResidualFormName(ResidualForm form) {
  return form == ResidualForm::kCartesian ? "cartesian" : "joint_space";
}

}  // namespace cellmetry
