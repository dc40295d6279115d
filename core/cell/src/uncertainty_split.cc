// The statistical and systematic parts of a cell's uncertainty (uncertainty_split.h).
#include "uncertainty_split.h"

#include <algorithm>
#include <set>

#include "cellmetry/estimation/robust_covariance.h"

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

// Each residual block's camera among `cameras` (ResidualInfo order); -1: kept in every estimate.
std::vector<int> CameraGroups(const Problem& problem, const std::vector<std::string>& cameras) {
  std::vector<int> groups;
  for (const auto& info : problem.residual_infos()) {
    const auto it = std::find(cameras.begin(), cameras.end(), info.camera);
    groups.push_back(info.kind == ResidualInfo::Kind::kPrior || it == cameras.end()
                         ? -1
                         : static_cast<int>(it - cameras.begin()));
  }
  return groups;
}

// Leave-one-camera-out deviations from the answer (none with fewer than two cameras).
std::vector<Eigen::VectorXd> CameraJackknife(const WorkcellProblem& spec,
                                             const Recording& recording, const Problem& problem,
                                             const Linearization& at) {
  if (spec.camera_model != CameraModel::kStaticCameras) return {};
  const std::vector<std::string> cameras = CamerasSeeingTools(spec, recording);
  if (cameras.size() < 2) return {};
  return LinearizedJackknife(problem, at, CameraGroups(problem, cameras),
                             spec.identifiability_tolerance);
}

}  // namespace

void SplitUncertainty(const WorkcellProblem& spec, const Recording& recording,
                      const AssembledWorkcell& fitted, const Linearization& at, Uncertainty* u) {
  const Problem& problem = fitted.problem;
  const Eigen::MatrixXd cluster = ClusterRobustCovariance(problem, at, PoseClusters(problem), *u);
  const auto deviations = CameraJackknife(spec, recording, problem, at);
  CombineUncertainty(cluster, deviations.size() >= 2 ? JackknifeSpread(deviations) : Jackknife{},
                     u);
}

}  // namespace cellmetry
