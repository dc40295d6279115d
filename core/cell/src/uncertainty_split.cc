// The statistical and systematic parts of a cell's uncertainty (uncertainty_split.h).
#include "uncertainty_split.h"

#include <algorithm>
#include <future>
#include <map>

#include "camera_left_out_fit.h"
#include "cellmetry/estimation/robust_covariance.h"

namespace cellmetry {

std::vector<int> PoseClustersInCaptureOrder(const Problem& problem) {
  std::map<int, int> first_sample;  // pose -> the first sample that shows it
  for (const auto& info : problem.residual_infos()) {
    if (info.kind == ResidualInfo::Kind::kPrior) continue;
    const auto [it, added] = first_sample.emplace(info.pose, info.sample);
    if (!added) it->second = std::min(it->second, info.sample);
  }
  std::vector<std::pair<int, int>> order;  // (first sample, pose)
  for (const auto& [pose, sample] : first_sample) order.push_back({sample, pose});
  std::sort(order.begin(), order.end());
  std::map<int, int> rank;
  for (size_t i = 0; i < order.size(); ++i) rank[order[i].second] = static_cast<int>(i);
  std::vector<int> clusters;
  for (const auto& info : problem.residual_infos()) {
    clusters.push_back(info.kind == ResidualInfo::Kind::kPrior ? -1 : rank.at(info.pose));
  }
  return clusters;
}

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

void SplitUncertainty(const WorkcellProblem& spec, const Recording& recording,
                      const AssembledWorkcell& fitted, const Linearization& at, Uncertainty* u) {
  const Problem& problem = fitted.problem;
  // Leave-one-camera-out deviations from the answer. The jackknife and the cluster-robust
  // covariance read the answer's linearization and nothing else: the jackknife on another core
  // meanwhile, where there is one.
  const std::vector<std::string> cameras = CamerasToLeaveOut(spec, recording);
  std::future<std::vector<Eigen::VectorXd>> jackknife = std::async(
      cameras.empty() ? std::launch::deferred : std::launch::async, [&] {
        if (cameras.empty()) return std::vector<Eigen::VectorXd>{};
        return LinearizedJackknife(problem, at, CameraGroups(problem, cameras),
                                   spec.identifiability_tolerance);
      });
  const ClusterRobust cluster =
      SerialClusterRobustCovariance(problem, at, PoseClustersInCaptureOrder(problem), *u);
  const auto deviations = jackknife.get();
  CombineUncertainty(cluster.covariance,
                     deviations.size() >= 2 ? JackknifeSpread(deviations) : Jackknife{}, u);
  u->correlated_poses = cluster.lag;
}

}  // namespace cellmetry
