// The workcell identification (workcell.h) as the sequence of its stages. What a stage does is
// in workcell_fit.cc, workcell_description.cc and workcell_warnings.cc; what runs on the other
// core meanwhile, in input_link_schedule.h. Each function comes before its callers:
// IdentifyOnce identifies a recording as it is (the fit with sigma, covariance and residuals,
// the inputs' part, the description, cross-validation, warnings); IdentifyFromStart leaves
// outliers out around it and each camera out after it; IdentifyWorkcell picks the cameras and
// the starts.
#include "cellmetry/cell/workcell.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/basics/stage_clock.h"
#include "cellmetry/cell/joint_ranges.h"
#include "cellmetry/cell/outliers.h"
#include "cellmetry/cell/robot_pairs.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "camera_left_out_fit.h"
#include "far_start.h"
#include "fit_once.h"
#include "input_link_schedule.h"
#include "input_uncertainty.h"
#include "residual_rows.h"
#include "uncertainty_split.h"
#include "workcell_description.h"
#include "workcell_fit.h"
#include "workcell_warnings.h"

namespace cellmetry {

namespace {

// What the fit starts from, as the result reports it.
void RecordFitInputs(const FitInputs& inputs, WorkcellResult* result) {
  result->skipped = inputs.data.skipped;
  result->repeatability = inputs.repeatability;
  result->noise = inputs.noise;
  result->start = inputs.start;
}

// The fit's answer, as the result reports it.
void RecordFitAnswer(const WorkcellProblem& spec, const Fit& fit, WorkcellResult* result) {
  result->solver = fit.summary;
  result->unidentifiable = fit.unidentifiable;
  result->estimate = ReadEstimate(spec, *fit.assembled);
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

// One identification on `recording` as it is. `solved`: the robust first fit's least-squares
// fit of this very recording (a Cartesian job), which is the plain fit's first solve: its data,
// noise, start, answer and inputs' link are taken, not made again.
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
  RecordFitInputs(inputs, &result);
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
  RecordFitAnswer(spec, fit, &result);
  clock.Lap("solve");
  LinkInputsAtTheAnswer(spec, recording, data, result.noise, fit, solved.get(), &input_link);
  // The solve's last identifiability check linearized here already (with its R factor).
  const Linearization at_answer =
      fit.at_answer.valid ? std::move(fit.at_answer) : Linearize(fit.assembled->problem);
  AddCovarianceAndResiduals(spec, recording, data, fit, at_answer, &input_link, &clock, &result);
  AddInputUncertainty(input_link.Take(), &result.uncertainty);  // rethrows what the link threw
  const HeldParameters held = HeldOf(result.unidentifiable);
  DescribeEstimate(spec, held.held, &result);
  RecordJointRanges(recording, &result);
  AddModelWarnings(spec, &result);
  result.robot_to_robot = RobotToRobot(result);
  clock.Lap("input_uncertainty");
  result.held_out =
      CrossValidate(spec, recording, data, result.noise, result.estimate, held, make_solver);
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

// The outlier test on the plain fit's own rows (outliers.h): what fails it is left out of
// `kept` (and added to `outliers`) and the cell identified again, twice at most (what the first
// ones masked shows in the second pass); each pass's stages are numbered by it.
void IdentifyWithoutPlainOutliers(const WorkcellProblem& spec, const SolverMaker& make_solver,
                                  Recording* kept, std::vector<Outlier>* outliers,
                                  WorkcellResult* result) {
  const int passes = spec.outlier_test == OutlierTest::kOff ? 0 : 2;
  for (int pass = 0; pass < passes; ++pass) {
    const std::vector<Outlier> found = FindOutliers(result->residuals, *kept);
    if (found.empty()) break;
    Progress::Note(std::to_string(found.size()) +
                   " residual rows fail the outlier test; "
                   "identifying again without their observations");
    outliers->insert(outliers->end(), found.begin(), found.end());
    *kept = WithoutOutliers(*kept, found);
    std::vector<StageTime> stages = std::move(result->stages);
    *result = IdentifyOnce(spec, *kept, make_solver);
    for (StageTime& stage : result->stages) stage.pass = pass + 1;
    result->stages.insert(result->stages.begin(), stages.begin(), stages.end());
  }
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

// The identification from the job's starts (or the closed form where it gives none).
WorkcellResult IdentifyFromStart(const WorkcellProblem& spec, const Recording& recording,
                                 const SolverMaker& make_solver) {
  // Gross outliers (outliers.h): those a robust first fit finds are left out before the plain
  // fit; then what the plain fit's own residuals show, left out and the cell identified again
  // (IdentifyWithoutPlainOutliers). Clean data: the plain answer, untouched.
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
    Progress::Note(std::to_string(outliers.size()) +
                   " residual rows of a robust fit fail the "
                   "outlier test; fitting without their observations");
  }
  Recording kept = outliers.empty() ? Recording{} : WithoutOutliers(recording, outliers);
  const Recording& first = outliers.empty() ? recording : kept;
  WorkcellResult result = IdentifyOnce(spec, first, make_solver, std::move(solved));
  result.stages.insert(result.stages.begin(), clock.stages().begin(), clock.stages().end());
  if (outliers.empty()) kept = recording;
  IdentifyWithoutPlainOutliers(spec, make_solver, &kept, &outliers, &result);
  result.outliers = outliers;
  AddCamerasLeftOut(spec, kept, make_solver, &result);
  if (!outliers.empty()) NumberByOriginal(recording, kept, &result.residuals);
  return result;
}

// The identification from the job's far starts and from the closed form's (`closed`, the job
// without its starts), both scored by how well each predicts the carried targets of the
// recording (the same rows for both, whatever each left out as outliers): the better kept, the
// choice a warning.
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

// `spec` without the cameras it does not use (what IdentifyWorkcell then fits).
WorkcellProblem WithoutUnusedCameras(const WorkcellProblem& spec) {
  WorkcellProblem out = spec;
  for (auto it = out.cameras.begin(); it != out.cameras.end();) {
    it = it->second.use ? std::next(it) : out.cameras.erase(it);
  }
  return out;
}

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

RecordingScore ScoreOnRecording(const WorkcellProblem& spec, const WorkcellResult& result,
                                const Recording& fresh) {
  RecordingScore score;
  score.recording = fresh.folder;
  const WorkcellData data = PrepareWorkcellData(spec, fresh);
  const NoiseModel noise = BuildNoiseModel(fresh, spec.noise);
  WorkcellProblem cartesian = spec;
  cartesian.residual = ResidualForm::kCartesian;
  // The position rows of the robots' targets.
  const auto robot_rows = [&](const WorkcellEstimate& estimate) {
    std::vector<ResidualRow> rows;
    for (ResidualRow& row :
         ResidualRows(*AssembleWorkcell(cartesian, fresh, data, noise, estimate))) {
      if (row.kind == ResidualKind::kPosition && MeasuresARobot(fresh, row)) rows.push_back(row);
    }
    return rows;
  };
  for (const ResidualRow& row : robot_rows(result.start)) score.before.Add(row.error);
  score.before.Finish();
  const std::vector<ResidualRow> after = robot_rows(result.estimate);
  for (const ResidualRow& row : after) {
    score.after.Add(row.error);
    score.mean_after_mm += row.error.norm();
    score.max_after_mm = std::max(score.max_after_mm, row.error.norm());
  }
  if (!after.empty()) score.mean_after_mm /= static_cast<double>(after.size());
  score.after.Finish();
  MarkBeyondCalibration(result, fresh, after, &score);
  return score;
}

}  // namespace cellmetry
