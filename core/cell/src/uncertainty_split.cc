// The statistical and systematic parts of a cell's uncertainty (uncertainty_split.h).
#include "uncertainty_split.h"

#include <algorithm>
#include <future>
#include <map>

#include "cellmetry/estimation/robust_covariance.h"
#include "camera_left_out_fit.h"

namespace cellmetry {

std::vector<int> PoseClustersInCaptureOrder(const AssembledWorkcell& assembled) {
  std::map<int, int> first_sample;  // pose -> the first sample that shows it
  for (const MeasurementLabel& label : assembled.labels) {
    const auto [it, added] = first_sample.emplace(label.pose, label.sample);
    if (!added) it->second = std::min(it->second, label.sample);
  }
  std::vector<std::pair<int, int>> order;  // (first sample, pose)
  for (const auto& [pose, sample] : first_sample) order.push_back({sample, pose});
  std::sort(order.begin(), order.end());
  std::map<int, int> rank;
  for (size_t i = 0; i < order.size(); ++i) rank[order[i].second] = static_cast<int>(i);
  const size_t num_blocks = assembled.problem.residual_infos().size();
  std::vector<int> clusters;
  clusters.reserve(num_blocks);
  for (size_t b = 0; b < num_blocks; ++b) {
    const MeasurementLabel* label = assembled.LabelOf(b);
    clusters.push_back(label ? rank.at(label->pose) : -1);
  }
  return clusters;
}

std::vector<int> CameraGroups(const AssembledWorkcell& assembled,
                              const std::vector<std::string>& cameras) {
  const size_t num_blocks = assembled.problem.residual_infos().size();
  std::vector<int> groups;
  groups.reserve(num_blocks);
  for (size_t b = 0; b < num_blocks; ++b) {
    const MeasurementLabel* label = assembled.LabelOf(b);
    const auto it =
        label ? std::find(cameras.begin(), cameras.end(), label->camera) : cameras.end();
    groups.push_back(it == cameras.end() ? -1 : static_cast<int>(it - cameras.begin()));
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
  std::future<std::vector<Eigen::VectorXd>> jackknife =
      std::async(cameras.empty() ? std::launch::deferred : std::launch::async, [&] {
        if (cameras.empty()) return std::vector<Eigen::VectorXd>{};
        return LinearizedJackknife(problem, at, CameraGroups(fitted, cameras),
                                   spec.identifiability_tolerance);
      });
  const ClusterRobust cluster =
      SerialClusterRobustCovariance(problem, at, PoseClustersInCaptureOrder(fitted), *u);
  const auto deviations = jackknife.get();
  CombineUncertainty(cluster.covariance,
                     deviations.size() >= 2 ? JackknifeSpread(deviations) : Jackknife{}, u);
  u->correlated_poses = cluster.lag;
}

}  // namespace cellmetry
