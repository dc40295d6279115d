// The fit steps of a cell's identification (workcell_fit.h, fit_once.h): one fit, the fit with
// sigma, the rows a fit is judged by, and the cross-validation (workcell.h) built of them.
#include "workcell_fit.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <random>
#include <string>
#include <utility>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/basics/statistics.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/estimation/reweighted_solve.h"
#include "residual_rows.h"

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

bool MeasuresARobot(const Recording& recording, const ResidualRow& row) {
  return recording.IsCarried(row.target) || recording.camera_mounts.count(row.camera) > 0;
}

std::vector<ResidualRow> MeasurementRows(const WorkcellProblem& spec, const Recording& recording,
                                         const WorkcellData& data, const NoiseModel& noise,
                                         const WorkcellEstimate& estimate,
                                         const std::set<int>& poses, AssembledWorkcell* fitted,
                                         const Linearization* at) {
  if (spec.residual == ResidualForm::kCartesian && fitted) return ResidualRows(*fitted, at);
  WorkcellProblem cartesian = spec;
  cartesian.residual = ResidualForm::kCartesian;
  auto assembled = AssembleWorkcell(cartesian, recording, data, noise, estimate, poses);
  return ResidualRows(*assembled);
}

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

Fit FitWithSigma(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
                 const WorkcellEstimate& start, const SolverMaker& make_solver, NoiseModel* noise,
                 Fit* solved, InputLinkSchedule* input_link) {
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

namespace {

// The poses of `data`'s carried-target observations, each once, sorted.
std::vector<int> PosesOf(const Recording& recording, const WorkcellData& data) {
  std::vector<int> poses;
  for (const auto& m : data.tools) poses.push_back(recording.samples[m.sample_index].pose);
  std::sort(poses.begin(), poses.end());
  poses.erase(std::unique(poses.begin(), poses.end()), poses.end());
  return poses;
}

// One fold: the cell refitted on `train`, warm from `answer` with `held` held, and its rows
// that measure a robot on the poses `test` holds out.
std::vector<ResidualRow> HeldOutRows(const WorkcellProblem& spec, const Recording& recording,
                                     const WorkcellData& data, const NoiseModel& noise,
                                     const WorkcellEstimate& answer, const HeldParameters& held,
                                     const SolverMaker& make_solver, const std::set<int>& train,
                                     const std::set<int>& test) {
  Fit fit = FitOnce(spec, recording, data, noise, answer, train, held, make_solver,
                    /*warm_start=*/true);
  const WorkcellEstimate trained = ReadEstimate(spec, *fit.assembled);
  std::vector<ResidualRow> held_out;
  for (auto& row : MeasurementRows(spec, recording, data, noise, trained, test, nullptr)) {
    if (MeasuresARobot(recording, row)) held_out.push_back(std::move(row));
  }
  return held_out;
}

// One fold's held-out rows added to `out`: its positions' RMS per camera, in all and in the
// fold, and its normalized RMS over every row the fit uses (rotations too, where an effect may
// show most: a delta platform's tilt).
void AddFold(const std::vector<ResidualRow>& held_out, HeldOut* out) {
  ResidualRms fold;
  double normalized_ss = 0.0;
  int normalized_rows = 0;
  for (const auto& row : held_out) {
    normalized_ss += row.normalized.squaredNorm();
    normalized_rows += 3;
    if (row.kind != ResidualKind::kPosition) continue;
    out->total.Add(row.error);
    out->errors.push_back({row.observation, row.pose, row.error.squaredNorm()});
    out->per_camera[row.camera].Add(row.error);
    fold.Add(row.error);
  }
  out->per_fold_normalized_rms.push_back(
      normalized_rows > 0 ? std::sqrt(normalized_ss / normalized_rows) : 0.0);
  fold.Finish();
  out->per_fold.push_back(fold);
}

std::vector<double> SquaredErrorsOf(const HeldOut& held_out) {
  std::vector<double> squared;
  squared.reserve(held_out.errors.size());
  for (const HeldOutError& e : held_out.errors) squared.push_back(e.squared_mm2);
  return squared;
}

std::vector<int> PoseOfEachError(const HeldOut& held_out) {
  std::vector<int> poses;
  poses.reserve(held_out.errors.size());
  for (const HeldOutError& e : held_out.errors) poses.push_back(e.pose);
  return poses;
}

bool SameRows(const HeldOut& a, const HeldOut& b) {
  return a.folds == b.folds && a.errors.size() == b.errors.size() &&
         std::equal(a.errors.begin(), a.errors.end(), b.errors.begin(),
                    [](const HeldOutError& x, const HeldOutError& y) {
                      return x.observation == y.observation;
                    });
}

}  // namespace

HeldOutGain CompareHeldOut(const HeldOut& before, const HeldOut& after) {
  HeldOutGain gain;
  gain.gain_mm = before.total.norm - after.total.norm;
  gain.paired = SameRows(before, after) && before.errors.size() >= 2;
  gain.standard_error_mm =
      gain.paired ? RmsDifferenceStandardError(SquaredErrorsOf(before), SquaredErrorsOf(after),
                                               PoseOfEachError(before))
                  : std::hypot(before.total_se_mm, after.total_se_mm);
  return gain;
}

HeldOut CrossValidate(const WorkcellProblem& spec, const Recording& recording,
                      const WorkcellData& data, const NoiseModel& noise,
                      const WorkcellEstimate& answer, const HeldParameters& held,
                      const SolverMaker& make_solver) {
  HeldOut out;
  std::vector<int> poses = PosesOf(recording, data);
  const int folds = std::min<int>(spec.folds, static_cast<int>(poses.size()));
  if (folds < 2) return out;
  std::mt19937 rng(spec.seed);
  std::shuffle(poses.begin(), poses.end(), rng);
  out.folds = folds;
  // The folds side by side (each fit's own threads leave its serial parts to overlap), then
  // summed in fold order, so that the answer does not depend on which finished first.
  std::vector<std::vector<ResidualRow>> held_out(folds);
  Progress progress("cross-validation (" + CameraModelName(spec.camera_model) + ") fold", folds);
  std::mutex progress_mutex;
  tbb::parallel_for(0, folds, [&](int f) {
    std::set<int> train, test;
    for (size_t i = 0; i < poses.size(); ++i) {
      (static_cast<int>(i) % folds == f ? test : train).insert(poses[i]);
    }
    held_out[f] = HeldOutRows(spec, recording, data, noise, answer, held, make_solver, train, test);
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress.Advance();
  });
  for (const std::vector<ResidualRow>& fold : held_out) AddFold(fold, &out);
  out.total.Finish();
  if (!out.errors.empty()) {
    out.total_se_mm =
        RmsWithStandardError(SquaredErrorsOf(out), PoseOfEachError(out)).standard_error;
  }
  for (auto& [camera, rms] : out.per_camera) rms.Finish();
  return out;
}

}  // namespace cellmetry
