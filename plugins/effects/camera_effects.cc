// Constructors and descriptions of the camera-side effects: target_scale.h, camera_intrinsics.h,
// target_tilt.h. Each parameter says how large its physics plausibly is.
#include "camera_intrinsics.h"
#include "describe.h"
#include "target_scale.h"
#include "target_tilt.h"

namespace cellmetry::effects {

TargetScale::TargetScale(std::vector<std::string> targets, bool shared)
    : targets_(std::move(targets)), shared_(shared) {
  for (const auto& target : targets_) {
    if (shared_ && !parameters_.empty()) break;
    parameters_.push_back({shared_ ? std::string("scale") : target + ".scale",
                           "1",
                           0.0,
                           false,
                           {},
                           {},
                           {},
                           shared_ ? "relative error of the targets' printed size (one printer)"
                                   : "relative error of the target's printed size",
                           {}});
    parameters_.back().plausible = 0.02;  // a printer's scaling, a board's stated square size
  }
}

std::string TargetScale::Describe(const std::vector<double>& params) const {
  return WithParameters("target printed at another size than stated", parameters_, params);
}

CameraIntrinsics::CameraIntrinsics(std::vector<std::string> cameras, IntrinsicsTerms terms)
    : cameras_(std::move(cameras)), terms_(terms),
      lens_(terms.radial || terms.k2 || terms.tangential), principal_at_(int(terms.focal)),
      lens_at_(principal_at_ + 2 * int(terms.principal)),
      terms_per_camera_(lens_at_ + int(terms.radial) + int(terms.k2) + 2 * int(terms.tangential)) {
  auto add = [&](const std::string& name, const std::string& unit, const std::string& what,
                 double plausible) {
    parameters_.push_back({name, unit, 0.0, false, {}, {}, {}, what, {}});
    parameters_.back().plausible = plausible;
  };
  for (const auto& camera : cameras_) {
    // The order ApplyT reads them in: [focal] [px py] [k1] [k2] [p1 p2].
    if (terms_.focal) {  // a factory calibration's focal length
      add(camera + ".focal_scale", "1",
          "relative error of the focal length (measured depth alone scales)", 0.03);
    }
    if (terms_.principal) {
      for (const char* axis : {"x", "y"}) {  // about 18 px at f = 900 px
        add(camera + ".principal_" + axis, "rad",
            std::string("principal point error / focal length along ") + axis, 0.02);
        // Several cameras' shifts are judged as what they share and what is each one's own
        // (plausibility.h): a cause common to cameras calibrated alike -- the intrinsics of
        // another image format or crop, one procedure's bias -- shifts every principal point by
        // the same pixels, up to about 45 px at f = 900 px.
        parameters_.back().plausible_group = std::string("principal point ") + axis;
        parameters_.back().plausible_common = 0.05;
      }
    }
    // A lens's coefficients against a factory calibration's: k1 and k2 errors of a few hundredths
    // at the normalized radii a board is seen at (r < 0.6), decentring a thousandth or two.
    if (terms_.radial) {
      add(camera + ".radial_k1", "1", "radial distortion error at unit normalized radius", 0.05);
    }
    if (terms_.k2) {
      add(camera + ".radial_k2", "1", "fourth-order radial distortion error (r^4 term)", 0.1);
    }
    if (terms_.tangential) {
      for (const char* p : {"p1", "p2"}) {
        add(camera + ".tangential_" + p, "1", std::string("tangential (decentring) error ") + p,
            0.005);
      }
    }
  }
}

std::string CameraIntrinsics::Describe(const std::vector<double>& params) const {
  std::string what = "camera intrinsics off as seen in the measured poses";
  const bool lens_only = !terms_.focal && !terms_.principal;
  if (terms_.focal && !terms_.principal && !lens_) {
    what = "camera focal length off (measured depth scales alone)";
  } else if (terms_.principal && !terms_.focal && !lens_) {
    what = "camera principal point off (the rays turn)";
  } else if (lens_only && terms_.radial && !terms_.k2 && !terms_.tangential) {
    what = "camera radial distortion off (errors grow with image radius)";
  } else if (lens_only) {
    what = "camera lens distortion off (errors grow towards the image's edges)";
  }
  return WithParameters(what, parameters_, params);
}

TargetTilt::TargetTilt(std::vector<std::string> targets, bool world, bool turn)
    : targets_(std::move(targets)), world_(world), turn_(turn) {
  const std::vector<std::string> axes =
      turn_ ? std::vector<std::string>{"x", "y", "z"} : std::vector<std::string>{"x", "y"};
  for (const auto& target : targets_) {
    for (const auto& axis : axes) {
      const std::string name = (world_ ? std::string("world_frame") : target) + ".tilt_" + axis;
      parameters_.push_back({name,
                             "rad",
                             0.0,
                             false,
                             {},
                             {},
                             {},
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
