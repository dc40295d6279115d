// OpenCV's closed-form hand-eye methods behind one call, in cellmetry's frame names, for the
// hand-eye comparison (hand_eye_compare.h).
//
// Both setups are one equation with the roles named differently. With A_i = T_base_flange(q_i)
// and B_i = T_cam_board measured at capture i:
//   eye-in-hand (camera on the flange, board static):  T_base_board = A_i X B_i, X = T_flange_cam
//   eye-to-hand (camera static, board on the flange):  T_base_cam B_i = A_i T_flange_board, so
//     with A'_i = A_i^-1 = T_flange_base and B'_i = B_i: T_flange_board = A'_i X B_i,
//     X = T_base_cam
// cv::calibrateHandEye solves AX = XB from pairs of captures (it takes A as "gripper2base" and B
// as "target2cam", and returns X as "cam2gripper"); cv::calibrateRobotWorldHandEye solves
// AX = ZB from the captures themselves (Shah 2013 eq. 9; Li et al. 2010 eq. 26), taking the
// camera-to-world pose as "world2cam" and the base-to-gripper pose as "base2gripper".
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

struct HandEyeCaptures {
  std::vector<Pose> T_base_flange;  // the robot at each capture (nominal model, recorded joints)
  std::vector<Pose> T_cam_board;    // the board measured in the camera at the same capture
  bool eye_in_hand = false;         // the camera rides on the flange
};

// The OpenCV methods by their labels (opencv_tsai ... opencv_li), in the order they are run.
const std::vector<std::string>& OpenCvHandEyeMethods();

// "" when this OpenCV implements `method` soundly, else its known fault in a few words. Before
// OpenCV 4.10 (opencv/opencv#24871, fixed by #24897) Tsai's method uses pairs of captures whose
// relative rotation is near 0 or 180 degrees, and Horaud's quaternions and Daniilidis's dual
// quaternions are not brought to one sign: each can miss on exact data (Debian's OpenCV is 4.6).
std::string OpenCvHandEyeFault(const std::string& method);

// The hand-eye frame by one OpenCV method: T_flange_cam (eye-in-hand) or T_base_cam
// (eye-to-hand). Throws std::invalid_argument for an unknown label; OpenCV's own errors
// (too few captures) pass through as cv::Exception.
Pose OpenCvHandEye(const std::string& method, const HandEyeCaptures& captures);

}  // namespace cellmetry
