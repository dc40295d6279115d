// Robot-to-robot transforms with sigma from the bases' joint covariance (robot_pairs.h).
#include "cellmetry/cell/robot_pairs.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "cellmetry/model/frame_block.h"

namespace cellmetry {

Eigen::Matrix<double, 12, 12> FramePairCovariance(const Uncertainty& u, const std::string& a,
                                                  const std::string& b) {
  std::array<int, 12> index;
  for (int i = 0; i < 12; ++i) {
    const std::string name = (i < 6 ? a : b) + "." + kFrameParameterNames[i % 6];
    const auto it = std::find(u.names.begin(), u.names.end(), name);
    index[i] = it == u.names.end() ? -1 : static_cast<int>(it - u.names.begin());
  }
  const bool have_correlation = u.correlation.rows() == static_cast<Eigen::Index>(u.names.size()) &&
                                u.sigma.size() == static_cast<Eigen::Index>(u.names.size());
  Eigen::Matrix<double, 12, 12> c = Eigen::Matrix<double, 12, 12>::Zero();
  for (int i = 0; i < 12; ++i) {
    for (int k = 0; k < 12; ++k) {
      if (index[i] < 0 || index[k] < 0) continue;
      c(i, k) = have_correlation
                    ? u.sigma[index[i]] * u.sigma[index[k]] * u.correlation(index[i], index[k])
                    : u.covariance(index[i], index[k]);
    }
  }
  return c;
}

std::vector<RobotPairEstimate> RobotToRobot(const WorkcellResult& result) {
  std::vector<const FrameEstimate*> bases;  // each robot's base, in the job's order
  for (const auto& robot : result.robot_models) {
    for (const auto& f : result.frames) {
      if (f.name == robot.robot + ".base" && f.parent == "world") bases.push_back(&f);
    }
  }
  std::vector<RobotPairEstimate> pairs;
  for (size_t i = 0; i < bases.size(); ++i) {
    for (size_t j = 0; j < bases.size(); ++j) {
      if (i == j) continue;
      const FrameEstimate& a = *bases[i];
      const FrameEstimate& b = *bases[j];
      const RelativePose relative =
          PoseInFrame(a.pose, b.pose, FramePairCovariance(result.uncertainty, a.name, b.name));
      RobotPairEstimate pair;
      pair.covariance = relative.covariance;
      pair.frame.name = b.name;
      pair.frame.parent = a.name;
      pair.frame.pose = relative.T_a_b;
      const Eigen::Matrix<double, 6, 1> sigma =
          relative.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
      pair.frame.sigma_mm = sigma.head<3>();
      pair.frame.sigma_rad = sigma.tail<3>();
      pair.frame.sigma_statistical = sigma;  // the parts do not propagate apart; all in one
      for (int k = 0; k < 6; ++k) pair.frame.held[k] = a.held[k] && b.held[k] && sigma[k] == 0.0;
      pairs.push_back(pair);
    }
  }
  return pairs;
}

}  // namespace cellmetry
