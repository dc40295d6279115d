// OpenCV's hand-eye methods in cellmetry's frame names (opencv_hand_eye.h).
#include "opencv_hand_eye.h"

#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/core/version.hpp>

namespace cellmetry {
namespace {

struct CvPoses {
  std::vector<cv::Mat> R, t;
};

CvPoses ToCv(const std::vector<Pose>& poses) {
  CvPoses out;
  for (const Pose& pose : poses) {
    cv::Mat R, t;
    cv::eigen2cv(pose.R, R);
    cv::eigen2cv(pose.t, t);
    out.R.push_back(R);
    out.t.push_back(t);
  }
  return out;
}

Pose FromCv(const cv::Mat& R, const cv::Mat& t) {
  Pose pose;
  cv::cv2eigen(R, pose.R);
  cv::cv2eigen(t, pose.t);
  return pose;
}

std::vector<Pose> Inverses(const std::vector<Pose>& poses) {
  std::vector<Pose> out;
  for (const Pose& pose : poses) out.push_back(pose.inverse());
  return out;
}

// AX = XB with A = T_base_flange (eye-in-hand) or its inverse (eye-to-hand); see the header.
Pose CalibrateHandEye(cv::HandEyeCalibrationMethod method, const HandEyeCaptures& captures) {
  const CvPoses A =
      ToCv(captures.eye_in_hand ? captures.T_base_flange : Inverses(captures.T_base_flange));
  const CvPoses B = ToCv(captures.T_cam_board);
  cv::Mat R_x, t_x;
  cv::calibrateHandEye(A.R, A.t, B.R, B.t, R_x, t_x, method);
  return FromCv(R_x, t_x);
}

// AX = ZB. Eye-in-hand: world = the board, T_cam_board = T_cam_flange T_flange_base T_base_board;
// the hand-eye frame is gripper2cam's inverse. Eye-to-hand: the board plays the camera and the
// camera the world, T_board_cam = T_board_flange T_flange_base T_base_cam; the hand-eye frame is
// base2world's inverse.
Pose CalibrateRobotWorldHandEye(cv::RobotWorldHandEyeCalibrationMethod method,
                                const HandEyeCaptures& captures) {
  const CvPoses world_to_cam =
      ToCv(captures.eye_in_hand ? captures.T_cam_board : Inverses(captures.T_cam_board));
  const CvPoses base_to_gripper = ToCv(Inverses(captures.T_base_flange));
  cv::Mat R_base_world, t_base_world, R_gripper_cam, t_gripper_cam;
  cv::calibrateRobotWorldHandEye(world_to_cam.R, world_to_cam.t, base_to_gripper.R,
                                 base_to_gripper.t, R_base_world, t_base_world, R_gripper_cam,
                                 t_gripper_cam, method);
  return captures.eye_in_hand ? FromCv(R_gripper_cam, t_gripper_cam).inverse()
                              : FromCv(R_base_world, t_base_world).inverse();
}

}  // namespace

const std::vector<std::string>& OpenCvHandEyeMethods() {
  static const std::vector<std::string> methods = {
      "opencv_tsai",       "opencv_park", "opencv_horaud", "opencv_andreff",
      "opencv_daniilidis", "opencv_shah", "opencv_li"};
  return methods;
}

std::string OpenCvHandEyeFault(const std::string& method) {
  const bool fixed = CV_VERSION_MAJOR > 4 || (CV_VERSION_MAJOR == 4 && CV_VERSION_MINOR >= 10);
  if (fixed) return "";
  if (method == "opencv_tsai") return "OpenCV " CV_VERSION ": uninformative pairs kept";
  if (method == "opencv_horaud" || method == "opencv_daniilidis") {
    return "OpenCV " CV_VERSION ": quaternion signs";
  }
  return "";
}

Pose OpenCvHandEye(const std::string& method, const HandEyeCaptures& captures) {
  if (method == "opencv_tsai") return CalibrateHandEye(cv::CALIB_HAND_EYE_TSAI, captures);
  if (method == "opencv_park") return CalibrateHandEye(cv::CALIB_HAND_EYE_PARK, captures);
  if (method == "opencv_horaud") return CalibrateHandEye(cv::CALIB_HAND_EYE_HORAUD, captures);
  if (method == "opencv_andreff") return CalibrateHandEye(cv::CALIB_HAND_EYE_ANDREFF, captures);
  if (method == "opencv_daniilidis") {
    return CalibrateHandEye(cv::CALIB_HAND_EYE_DANIILIDIS, captures);
  }
  if (method == "opencv_shah") {
    return CalibrateRobotWorldHandEye(cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH, captures);
  }
  if (method == "opencv_li") {
    return CalibrateRobotWorldHandEye(cv::CALIB_ROBOT_WORLD_HAND_EYE_LI, captures);
  }
  throw std::invalid_argument("unknown OpenCV hand-eye method " + method);
}

}  // namespace cellmetry
