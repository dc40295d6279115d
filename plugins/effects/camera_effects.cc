// Constructors and descriptions of the camera-side effects: target_scale.h, camera_intrinsics.h,
// target_tilt.h. Each parameter says how large its physics plausibly is.
#include "camera_intrinsics.h"
#include "describe.h"
#include "target_scale.h"
#include "target_tilt.h"

namespace cellmetry::effects {

TargetScale::TargetScale(std::vector<std::string> targets) : targets_(std::move(targets)) {
  for (const auto& target : targets_) {
    parameters_.push_back({target + ".scale", "1", 0.0, false, {}, {}, {},
                           "relative error of the target's printed size", {}});
    parameters_.back().plausible = 0.02;  // a printer's scaling, a board's stated square size
  }
}

std::string TargetScale::Describe(const std::vector<double>& params) const {
  return WithParameters("target printed at another size than stated", parameters_, params);
}

CameraIntrinsics::CameraIntrinsics(std::vector<std::string> cameras, bool focal, bool principal,
                                   bool radial)
    : cameras_(std::move(cameras)), focal_(focal), principal_(principal), radial_(radial),
      terms_per_camera_(int(focal) + 2 * int(principal) + int(radial)) {
  for (const auto& camera : cameras_) {
    if (focal_) {
      parameters_.push_back({camera + ".focal_scale", "1", 0.0, false, {}, {}, {},
                             "relative error of the focal length (measured depth alone scales)",
                             {}});
      parameters_.back().plausible = 0.03;  // a factory calibration's focal length
    }
    if (principal_) {
      for (const char* axis : {"x", "y"}) {
        parameters_.push_back({camera + ".principal_" + axis, "rad", 0.0, false, {}, {}, {},
                               std::string("principal point error / focal length along ") + axis,
                               {}});
        parameters_.back().plausible = 0.02;  // about 18 px at f = 900 px
      }
    }
    if (radial_) {
      parameters_.push_back({camera + ".radial_k1", "1", 0.0, false, {}, {}, {},
                             "radial distortion error at unit normalized radius", {}});
      parameters_.back().plausible = 0.05;
    }
  }
}

std::string CameraIntrinsics::Describe(const std::vector<double>& params) const {
  const int terms = int(focal_) + int(principal_) + int(radial_);
  std::string what = "camera intrinsics off as seen in the measured poses";
  if (terms == 1 && focal_) what = "camera focal length off (measured depth scales alone)";
  if (terms == 1 && principal_) what = "camera principal point off (the rays turn)";
  if (terms == 1 && radial_) what = "camera radial distortion off (errors grow with image radius)";
  return WithParameters(what, parameters_, params);
}

TargetTilt::TargetTilt(std::vector<std::string> targets, bool world, bool turn)
    : targets_(std::move(targets)), world_(world), turn_(turn) {
  const std::vector<std::string> axes =
      turn_ ? std::vector<std::string>{"x", "y", "z"} : std::vector<std::string>{"x", "y"};
  for (const auto& target : targets_) {
    for (const auto& axis : axes) {
      const std::string name = (world_ ? std::string("world_frame") : target) + ".tilt_" + axis;
      parameters_.push_back({name, "rad", 0.0, false, {}, {}, {},
                             world_ ? "world tag turned about its " + axis
                                    : "pose estimator's tilt about the target's " + axis,
                             {}});
      parameters_.back().plausible = world_ ? 0.02 : 0.03;  // 1 deg glued; 2 deg estimated
    }
  }
}

std::string TargetTilt::Describe(const std::vector<double>& params) const {
  return WithParameters(world_ ? "world tag turned from the frame the placement was measured in"
                               : "orientation bias of the target's pose estimates",
                        parameters_, params);
}

}  // namespace cellmetry::effects
