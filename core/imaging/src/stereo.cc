// StereoRig (stereo.h): a rig read from our YAML or OpenCV's stereo calibration, and
// maximum-likelihood triangulation of a keypoint pair with the point's covariance.
#include "cellmetry/imaging/stereo.h"
#include "cellmetry/model/camera_file.h"

#include <ceres/jet.h>

#include <opencv2/core.hpp>

#include <filesystem>
#include <fstream>

#include "cellmetry/basics/error.h"
#include "cellmetry/formats/config_fields.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/units.h"

namespace cellmetry {
namespace {

using Jet3 = ceres::Jet<double, 3>;

// Both projections of p (left frame) and their 4x3 Jacobian.
Eigen::Vector4d Project(const StereoRig& rig, const Eigen::Vector3d& p,
                        Eigen::Matrix<double, 4, 3>* J) {
  const Vector3<Jet3> pj(Jet3(p.x(), 0), Jet3(p.y(), 1), Jet3(p.z(), 2));
  const Vector2<Jet3> a = rig.left.Project(pj);
  const Vector3<Jet3> pr = rig.T_right_left.R.cast<Jet3>() * pj + rig.T_right_left.t.cast<Jet3>();
  const Vector2<Jet3> b = rig.right.Project(pr);
  const Jet3 all[4] = {a.x(), a.y(), b.x(), b.y()};
  Eigen::Vector4d out;
  for (int i = 0; i < 4; ++i) {
    out[i] = all[i].a;
    J->row(i) = all[i].v.transpose();
  }
  return out;
}

// Closest point between the two rays (left frame).
std::optional<Eigen::Vector3d> Midpoint(const StereoRig& rig, const Keypoint& left,
                                        const Keypoint& right) {
  const Pose T_left_right = rig.T_right_left.inverse();
  const Eigen::Vector3d o1 = Eigen::Vector3d::Zero(), d1 = rig.left.Ray(left.pixel).normalized();
  const Eigen::Vector3d o2 = T_left_right.t,
                        d2 = (T_left_right.R * rig.right.Ray(right.pixel)).normalized();
  const double b = d1.dot(d2);
  const double denom = 1.0 - b * b;
  if (denom < 1e-12) return std::nullopt;
  const Eigen::Vector3d w = o1 - o2;
  const double s = (b * d2.dot(w) - d1.dot(w)) / denom;
  const double t = (d2.dot(w) - b * d1.dot(w)) / denom;
  if (s <= 0 || t <= 0) return std::nullopt;
  return 0.5 * ((o1 + s * d1) + (o2 + t * d2));
}

StereoRig FromOpenCv(const std::string& path) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception&) {
    throw InputError({path, 0, 0}, "not a readable OpenCV stereo calibration",
                     "Give our YAML (stereo: {...}) or OpenCV's stereo calibration output");
  }
  auto matrix = [&](const char* key, int rows, int cols) {
    cv::Mat m;
    if (fs[key].empty()) {
      throw InputError({path, 0, 0}, std::string("missing field '") + key + "'",
                       "OpenCV stereo calibrations need M1 D1 M2 D2 R T image_width image_height");
    }
    fs[key] >> m;
    m.convertTo(m, CV_64F);
    if ((rows > 0 && m.rows != rows) || (cols > 0 && m.cols != cols)) {
      throw InputError({path, 0, 0}, std::string("field '") + key + "' has the wrong size",
                       "Check the calibration file");
    }
    return m;
  };
  StereoRig rig;
  for (int side = 0; side < 2; ++side) {
    PinholeCamera& c = side == 0 ? rig.left : rig.right;
    const cv::Mat K = matrix(side == 0 ? "M1" : "M2", 3, 3);
    const cv::Mat D = matrix(side == 0 ? "D1" : "D2", -1, -1);
    c.fx = K.at<double>(0, 0), c.fy = K.at<double>(1, 1);
    c.cx = K.at<double>(0, 2), c.cy = K.at<double>(1, 2);
    for (int i = 0; i < static_cast<int>(D.total()) && i < 5; ++i)
      c.distortion[i] = D.at<double>(i);
    if (fs["image_width"].empty() || fs["image_height"].empty()) {
      throw InputError({path, 0, 0}, "missing field 'image_width' or 'image_height'",
                       "Add the image size the calibration was made at");
    }
    c.width = static_cast<int>(fs["image_width"].real());
    c.height = static_cast<int>(fs["image_height"].real());
  }
  const cv::Mat R = matrix("R", 3, 3), T = matrix("T", -1, -1);
  if (T.total() != 3) throw InputError({path, 0, 0}, "field 'T' must have 3 entries");
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) rig.T_right_left.R(i, k) = R.at<double>(i, k);
    rig.T_right_left.t[i] = T.at<double>(i);
  }
  return rig;
}

// A ROS stereo pair's extrinsics from its two camera_info files (camera_calibration's
// stereo output, OpenCV's stereoRectify): each camera's rectification R turns it into the common
// rectified frame, and the right projection's P(0,3) = -fx' B (P(1,3) = -fy' B_y for a vertical
// rig) offsets the right rectified frame from the left one. So p_right = R_r^T (R_l p_left + t)
// with t = (P(0,3) / fx', P(1,3) / fy', 0), in the calibration's length unit.
Pose RosStereoExtrinsics(const RosCameraInfo& left, const RosCameraInfo& right, double to_mm) {
  const Eigen::Vector3d t_rect(right.P(0, 3) / right.P(0, 0), right.P(1, 3) / right.P(1, 1), 0.0);
  Pose T_right_left;
  T_right_left.R = right.R_rect_camera.transpose() * left.R_rect_camera;
  T_right_left.t = right.R_rect_camera.transpose() * t_rect * to_mm;
  return T_right_left;
}

// stereo: {left: FILE, right: FILE, T_right_left: {...}} with each camera in any format of
// camera_file.h, or, for two ROS camera_info files, the extrinsics from their R and P and
// `units: {length: m|mm}` saying which unit the calibration's baseline is in.
StereoRig FromCameraFiles(const ConfigNode& s) {
  StereoRig rig;
  std::optional<RosCameraInfo> ros[2];
  for (int side = 0; side < 2; ++side) {
    const ConfigNode node = s[side == 0 ? "left" : "right"];
    PinholeCamera& camera = side == 0 ? rig.left : rig.right;
    if (!node.IsScalar()) {
      camera = ReadCameraNode(node);
      continue;
    }
    const std::string file = s.ResolvePath(node.AsString());
    camera = ReadCamera(file);
    const ConfigNode parsed = ConfigNode::LoadFile(file);
    if (IsRosCameraInfo(parsed)) ros[side] = ReadRosCameraInfo(parsed);
  }
  if (s.Has("T_right_left")) {
    const ConfigNode t = s["T_right_left"];
    t.ExpectKeys({"xyz", "rvec"});
    rig.T_right_left = ReadPose(t);
    return rig;
  }
  if (!ros[0] || !ros[1] || !(ros[1]->P(0, 0) > 0) || !(ros[1]->P(1, 1) > 0)) {
    throw s.Error("missing 'T_right_left'",
                  "Give T_right_left, or two ROS camera_info files with rectification and "
                  "projection matrices (camera_calibration's stereo output)");
  }
  if (!s.Has("units")) {
    throw s.Error("missing 'units' for the ROS calibration's baseline",
                  "Add units: {length: m} (ROS calibrations measure in m) or {length: mm}");
  }
  rig.T_right_left = RosStereoExtrinsics(*ros[0], *ros[1], ReadUnits(s["units"]).to_mm);
  return rig;
}

}  // namespace

std::optional<TriangulatedPoint> Triangulate(const StereoRig& rig, const Keypoint& left,
                                             const Keypoint& right) {
  std::optional<Eigen::Vector3d> start = Midpoint(rig, left, right);
  if (!start) return std::nullopt;
  Eigen::Matrix4d W = Eigen::Matrix4d::Zero();
  W.topLeftCorner<2, 2>() = left.covariance_px2.inverse();
  W.bottomRightCorner<2, 2>() = right.covariance_px2.inverse();
  const Eigen::Vector4d measured(left.pixel.x(), left.pixel.y(), right.pixel.x(), right.pixel.y());
  Eigen::Vector3d p = *start;
  Eigen::Matrix<double, 4, 3> J;
  Eigen::Vector4d r;
  for (int i = 0; i < 20; ++i) {
    r = Project(rig, p, &J) - measured;
    const Eigen::Vector3d step = (J.transpose() * W * J).ldlt().solve(-J.transpose() * W * r);
    p += step;
    if (step.norm() < 1e-10 * p.norm()) break;
  }
  r = Project(rig, p, &J) - measured;
  const Eigen::Vector3d p_right = rig.T_right_left * p;
  if (p.z() <= 0 || p_right.z() <= 0) return std::nullopt;
  TriangulatedPoint out;
  out.p_left_mm = p;
  out.covariance_mm2 = (J.transpose() * W * J).inverse();
  out.reprojection_rms_px = std::sqrt(r.squaredNorm() / 4.0);
  return out;
}

StereoRig ReadStereoRig(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError({path, 0, 0}, "stereo calibration file not found",
                     "Give the path relative to the job file");
  }
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  if (first.rfind("%YAML", 0) == 0 || first.rfind("<?xml", 0) == 0) return FromOpenCv(path);
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"stereo"});
  const ConfigNode s = root["stereo"];
  s.ExpectKeys({"left", "right", "T_right_left", "units"});
  if (!s["left"].IsScalar() && !s["right"].IsScalar()) {  // both cameras written inline
    if (!s.Has("T_right_left")) throw s.Error("missing 'T_right_left'");
    StereoRig rig;
    rig.left = ReadCameraNode(s["left"]);
    rig.right = ReadCameraNode(s["right"]);
    const ConfigNode t = s["T_right_left"];
    t.ExpectKeys({"xyz", "rvec"});
    rig.T_right_left = ReadPose(t);
    return rig;
  }
  return FromCameraFiles(s);
}

StereoRig OakDLikeRig() {
  StereoRig rig;
  rig.left = rig.right = OakDLikeCamera();
  rig.T_right_left.t = Eigen::Vector3d(-75.0, 0.0, 0.0);
  return rig;
}

}  // namespace cellmetry
