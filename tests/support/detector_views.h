// Helpers for detector tests: a detector from one line of YAML, and the pose that shows a
// target's printed side to the camera (render.h draws it there).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/model/detector.h"
#include "support/test_support.h"

namespace cellmetry::testing {

// The built-in detector `yaml` describes ("{type: aruco, ...}").
inline std::unique_ptr<Detector> MakeDetector(const std::string& yaml) {
  const ConfigNode config = ConfigNode::LoadString(yaml, "test.yaml");
  return Plugins().CreateDetector(config["type"].AsString(), config);
}

inline Eigen::Matrix3d RotationDeg(const Eigen::Vector3d& axis, double degrees) {
  return Eigen::AngleAxisd(degrees * M_PI / 180.0, axis.normalized()).toRotationMatrix();
}

// The mean of the detector's layout points (target frame, mm).
inline Eigen::Vector3d LayoutCentre(const Detector& d) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : d.layout()) sum += p.p_target_mm;
  return sum / static_cast<double>(d.layout().size());
}

// The target with its first face's printed side toward the camera (the face's z axis toward
// it), turned by `tilt`, its layout's centre at `at` (camera frame, mm).
inline Pose Facing(const Detector& d, const std::vector<MarkerFace>& faces,
                   const Eigen::Vector3d& at, const Eigen::Matrix3d& tilt) {
  Pose T_cam_target;
  T_cam_target.R =
      tilt * RotationDeg(Eigen::Vector3d::UnitX(), 180) * faces[0].T_target_face.R.transpose();
  T_cam_target.t = at - T_cam_target.R * LayoutCentre(d);
  return T_cam_target;
}

}  // namespace cellmetry::testing
