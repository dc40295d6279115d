// Cameras left out (camera_left_out.h): the recording without them, and the cell identified
// again without each camera in turn.
#include "camera_left_out_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/basics/statistics.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/left_out_difference.h"
#include "uncertainty_split.h"

namespace cellmetry {

Recording WithoutCameras(const Recording& recording, const std::set<std::string>& cameras) {
  Recording out = recording;
  out.observations.clear();
  for (const auto& obs : recording.observations) {
    if (!cameras.count(obs.camera)) out.observations.push_back(obs);
  }
  out.cameras.clear();
  for (const auto& camera : recording.cameras) {
    if (!cameras.count(camera)) out.cameras.push_back(camera);
  }
  return out;
}

double CameraLeftOutFlagSigmas(int compared) {
  const double three_sigma = 2.0 * NormalSurvival(3.0);  // two-sided
  if (compared <= 1) return 3.0;
  return std::max(3.0, std::sqrt(ChiSquareQuantile(1.0 - three_sigma / compared, 1.0)));
}

std::set<std::string> UnusedCameras(const WorkcellProblem& spec) {
  std::set<std::string> unused;
  for (const auto& [camera, settings] : spec.cameras) {
    if (!settings.use) unused.insert(camera);
  }
  return unused;
}

std::vector<std::string> CamerasToLeaveOut(const WorkcellProblem& spec,
                                           const Recording& recording) {
  if (spec.camera_model != CameraModel::kStaticCameras) return {};
  std::set<std::string> carried;
  for (const auto& robot : spec.robots) {
    for (const auto& tool : robot.tools) carried.insert(tool.target);
  }
  // A camera already found is not looked up again: a set lookup and insertion per observation
  // was a tenth of the uncertainty split on exp_a.
  std::vector<std::string> seeing;
  for (const auto& obs : recording.observations) {
    if (std::find(seeing.begin(), seeing.end(), obs.camera) != seeing.end()) continue;
    if (carried.count(obs.target)) seeing.push_back(obs.camera);
  }
  if (seeing.size() < 2) return {};
  std::sort(seeing.begin(), seeing.end());
  return seeing;
}

namespace {

// Progress silenced while it lives, as it was after.
class QuietProgress {
 public:
  QuietProgress() : was_quiet_(Progress::quiet()) { Progress::SetQuiet(true); }
  ~QuietProgress() { Progress::SetQuiet(was_quiet_); }
  QuietProgress(const QuietProgress&) = delete;
  QuietProgress& operator=(const QuietProgress&) = delete;

 private:
  bool was_quiet_;
};

// A difference's sigma below this share of the coordinate's own: the camera left out did not
// inform it.
constexpr double kInformedShare = 1e-3;

// One fit's inputs part of a free parameter: per uncertain input, its one-sigma move.
std::map<std::string, double> InputEffects(const Uncertainty& u, const std::string& name) {
  std::map<std::string, double> effects;
  const auto it = std::find(u.names.begin(), u.names.end(), name);
  if (it == u.names.end()) return effects;
  const auto i = it - u.names.begin();
  for (size_t k = 0; k < u.input_names.size(); ++k) {
    effects[u.input_names[k]] = u.input_effect(i, static_cast<Eigen::Index>(k));
  }
  return effects;
}

// The variance the shared inputs give the difference: each input moves both answers, by the
// difference of its two effects.
double InputsVariance(const Uncertainty& without, const Uncertainty& all, const std::string& name) {
  std::map<std::string, double> difference = InputEffects(without, name);
  for (const auto& [input, effect] : InputEffects(all, name)) difference[input] -= effect;
  double variance = 0.0;
  for (const auto& [input, effect] : difference) variance += effect * effect;
  return variance;
}

const FrameEstimate* FindFrame(const WorkcellResult& result, const std::string& name) {
  for (const auto& f : result.frames) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

// Every robot's base and tool, as compared between the two answers.
std::vector<std::string> ComparedFrames(const WorkcellProblem& spec) {
  std::vector<std::string> names;
  for (const auto& robot : spec.robots) {
    names.push_back(robot.name + ".base");
    for (const auto& tool : robot.tools) names.push_back(tool.target);
  }
  return names;
}

// A camera left out: what is reported of it, and its refit's whole result.
struct Refit {
  CameraLeftOut out;
  WorkcellResult result;
};

Refit IdentifyWithout(const WorkcellProblem& spec, const Recording& recording,
                      const std::string& camera, const SolverMaker& make_solver) {
  Refit refit;
  refit.out.camera = camera;
  WorkcellProblem without = spec;
  without.folds = 0;
  without.compare_camera_models = false;
  without.leave_one_camera_out = false;
  without.outlier_test = OutlierTest::kOff;  // the all-camera fit's outliers are out already
  without.cameras[camera].use = false;       // IdentifyWorkcell leaves its observations out
  try {
    const QuietProgress quiet;  // one line per camera, not the fits' own notes
    refit.result = IdentifyWorkcell(without, recording, make_solver);
  } catch (const InputError& e) {
    refit.out.error = e.what();
  }
  return refit;
}

// The gauge priors `refit` has and `all` has not, by `all`'s free columns.
std::map<int, double> AddedPriors(const WorkcellResult& refit, const WorkcellResult& all) {
  std::map<int, double> added;
  const HeldParameters had = HeldOf(all.unidentifiable);
  const auto& names = all.uncertainty.names;
  for (const auto& u : refit.unidentifiable) {
    if (u.prior_sigma <= 0.0 || had.prior_sigma.count(u.name)) continue;
    const auto it = std::find(names.begin(), names.end(), u.name);
    if (it != names.end()) added[static_cast<int>(it - names.begin())] = u.prior_sigma;
  }
  return added;
}

// The data's part of each difference's variance, per camera left out (left_out_difference.h),
// on the all-camera fit linearized again at its answer; empty where that fails.
std::vector<Eigen::VectorXd> DataVariances(const WorkcellProblem& spec, const Recording& recording,
                                           const WorkcellResult& all,
                                           const std::vector<std::string>& cameras,
                                           const std::vector<Refit>& refits) {
  const WorkcellData data = PrepareWorkcellData(spec, recording);
  auto fitted = AssembleWorkcell(spec, recording, data, all.noise, all.estimate);
  Problem& problem = fitted->problem;
  HoldParameters(&problem, HeldOf(all.unidentifiable));
  std::vector<std::string> names;
  for (const auto& p : problem.free_parameters()) names.push_back(p.name);
  if (names != all.uncertainty.names) return {};
  const Linearization at = Linearize(problem);
  std::vector<LeftOutGroup> groups;
  for (size_t c = 0; c < cameras.size(); ++c) {
    groups.push_back({static_cast<int>(c), AddedPriors(refits[c].result, all)});
  }
  return LeftOutDifferenceVariance(problem, at, CameraGroups(*fitted, cameras),
                                   PoseClustersInCaptureOrder(*fitted), all.uncertainty, groups,
                                   spec.identifiability_tolerance);
}

// `refit`'s bases and tools against `all`'s: `data_variance` the data's part per free parameter
// of `all` (NaN: the rest does not determine it).
void Compare(const WorkcellProblem& spec, const WorkcellResult& all,
             const Eigen::VectorXd& data_variance, Refit* refit) {
  CameraLeftOut& out = refit->out;
  const auto& names = all.uncertainty.names;
  for (const std::string& name : ComparedFrames(spec)) {
    const FrameEstimate* w = FindFrame(refit->result, name);
    const FrameEstimate* a = FindFrame(all, name);
    if (!w || !a) continue;
    FrameDifference d;
    d.frame = name;
    d.difference.head<3>() = w->pose.t - a->pose.t;
    d.difference.tail<3>() = RvecFromRotation(w->pose.R * a->pose.R.transpose());
    for (int i = 0; i < 6; ++i) {
      const std::string coordinate = name + "." + kFrameParameterNames[i];
      const auto it = std::find(names.begin(), names.end(), coordinate);
      if (w->held[i] || a->held[i] || w->undetermined[i] || it == names.end()) continue;
      const double data = data_variance.size() == static_cast<Eigen::Index>(names.size())
                              ? data_variance[it - names.begin()]
                              : std::numeric_limits<double>::quiet_NaN();
      if (std::isnan(data)) continue;
      d.sigma[i] =
          std::sqrt(data + InputsVariance(refit->result.uncertainty, all.uncertainty, coordinate));
      // A coordinate the left-out camera adds nothing to (both answers have it from the same
      // prior, or from the other cameras alone) has no difference to test.
      const double own = i < 3 ? w->sigma_mm[i] : w->sigma_rad[i - 3];
      d.compared[i] = d.sigma[i] > kInformedShare * own;
      if (!d.compared[i]) continue;
      const double sigmas = std::abs(d.difference[i]) / d.sigma[i];
      if (sigmas > out.worst_sigmas) {
        out.worst_sigmas = sigmas;
        out.worst = coordinate;
      }
    }
    out.frames.push_back(d);
  }
}

}  // namespace

std::vector<CameraLeftOut> LeaveEachCameraOut(const WorkcellProblem& spec,
                                              const Recording& recording, const WorkcellResult& all,
                                              const SolverMaker& make_solver) {
  const std::vector<std::string> cameras = CamerasToLeaveOut(spec, recording);
  if (cameras.empty()) return {};
  std::vector<Refit> refits;
  {
    Progress progress("leaving out camera", static_cast<int>(cameras.size()));
    for (const std::string& camera : cameras) {
      refits.push_back(IdentifyWithout(spec, recording, camera, make_solver));
      progress.Advance();
    }
  }
  const std::vector<Eigen::VectorXd> variances =
      DataVariances(spec, recording, all, cameras, refits);
  std::vector<CameraLeftOut> out;
  int compared = 0;
  for (size_t c = 0; c < refits.size(); ++c) {
    if (refits[c].out.error.empty() && c < variances.size()) {
      Compare(spec, all, variances[c], &refits[c]);
    }
    for (const FrameDifference& d : refits[c].out.frames) {
      compared += static_cast<int>(std::count(d.compared.begin(), d.compared.end(), true));
    }
    out.push_back(std::move(refits[c].out));
  }
  const double flag = CameraLeftOutFlagSigmas(compared);
  for (CameraLeftOut& c : out) c.flag_sigmas = flag;
  return out;
}

}  // namespace cellmetry
