// The statistical and systematic parts of a cell's uncertainty (uncertainty_split.h).
#include "uncertainty_split.h"

#include <cmath>
#include <limits>

#include "cellmetry/basics/progress.h"
#include "cellmetry/estimation/robust_covariance.h"
#include "fit_once.h"

namespace cellmetry {
namespace {

// The pose of each residual block (ResidualInfo order); priors are clusters of their own.
std::vector<int> PoseClusters(const Problem& problem) {
  std::vector<int> clusters;
  for (const auto& info : problem.residual_infos()) {
    clusters.push_back(info.kind == ResidualInfo::Kind::kPrior ? -1 : info.pose);
  }
  return clusters;
}

// Static cameras that see a target the job's robots carry: those a jackknife can leave out.
std::vector<std::string> CamerasSeeingTools(const WorkcellProblem& spec,
                                            const Recording& recording) {
  std::set<std::string> tools, seen;
  for (const auto& robot : spec.robots) {
    for (const auto& tool : robot.tools) tools.insert(tool.target);
  }
  for (const auto& obs : recording.observations) {
    if (tools.count(obs.target)) seen.insert(obs.camera);
  }
  return {seen.begin(), seen.end()};
}

Recording Without(const Recording& recording, const std::string& camera) {
  Recording out = recording;
  out.observations.clear();
  for (const auto& obs : recording.observations) {
    if (obs.camera != camera) out.observations.push_back(obs);
  }
  return out;
}

// The refit's deviation from the answer per free parameter of the full fit, NaN where the refit
// has no such parameter. Frame rotations start at zero about the answer (its rotation is the
// refit's reference), so their value is the deviation itself.
Eigen::VectorXd Deviation(const Problem& full, const Problem& refit) {
  const auto& names = full.free_parameters();
  const Eigen::VectorXd full_values = full.FreeValues();
  const Eigen::VectorXd refit_values = refit.FreeValues();
  std::map<std::string, int> index;
  for (size_t i = 0; i < refit.free_parameters().size(); ++i) {
    index[refit.free_parameters()[i].name] = static_cast<int>(i);
  }
  Eigen::VectorXd d = Eigen::VectorXd::Constant(names.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < names.size(); ++i) {
    const auto it = index.find(names[i].name);
    if (it == index.end()) continue;
    const std::string& name = names[i].name;
    const std::string last = name.substr(name.rfind('.') + 1);
    const bool rotation = names[i].unit == "rad" && (last == "rx" || last == "ry" || last == "rz");
    d[i] = refit_values[it->second] - (rotation ? 0.0 : full_values[i]);
  }
  return d;
}

// Leave-one-camera-out deviations from the answer (none with fewer than two cameras).
std::vector<Eigen::VectorXd> CameraJackknife(const WorkcellProblem& spec,
                                             const Recording& recording, const NoiseModel& noise,
                                             const WorkcellEstimate& answer,
                                             const std::set<std::string>& held,
                                             const SolverMaker& make_solver,
                                             const Problem& full) {
  std::vector<Eigen::VectorXd> deviations;
  if (spec.camera_model != CameraModel::kStaticCameras) return deviations;
  const std::vector<std::string> cameras = CamerasSeeingTools(spec, recording);
  if (cameras.size() < 2) return deviations;
  Progress progress("camera jackknife: refit without camera", static_cast<int>(cameras.size()));
  for (const std::string& camera : cameras) {
    const Recording reduced = Without(recording, camera);
    WorkcellEstimate start = answer;
    start.T_world_cam.erase(camera);
    const Fit fit = FitOnce(spec, reduced, PrepareWorkcellData(spec, reduced), noise, start, {},
                            held, make_solver);
    deviations.push_back(Deviation(full, fit.assembled->problem));
    progress.Advance();
  }
  return deviations;
}

}  // namespace

void SplitUncertainty(const WorkcellProblem& spec, const Recording& recording,
                      const NoiseModel& noise, const WorkcellEstimate& answer,
                      const std::set<std::string>& held, const SolverMaker& make_solver,
                      const AssembledWorkcell& fitted, const Linearization& at, Uncertainty* u) {
  const Problem& problem = fitted.problem;
  const Eigen::MatrixXd cluster = ClusterRobustCovariance(problem, at, PoseClusters(problem), *u);
  const auto deviations =
      CameraJackknife(spec, recording, noise, answer, held, make_solver, problem);
  CombineUncertainty(cluster, deviations.size() >= 2 ? JackknifeSpread(deviations) : Jackknife{},
                     u);
}

}  // namespace cellmetry
