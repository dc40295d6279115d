// ConcealedPhysics: physics a simulation hides in a recording that is NOT one of the effect
// library's equations, so that the physics finder (diagnosis.h) is tested against the world
// rather than against the formula it fits.
//
//   distributed_compliance  joint `joint` gives under gravity, with each link's mass spread
//                           along it (five points per link, not one) and a spring that stiffens
//                           with load: dq = c tau (1 - stiffening |tau| / tau_max)
//   dead_zone_backlash      joint `joint` follows its command through a dead zone of width b:
//                           a move drags it against one side of the play, short moves take up
//                           only part of it (friction), and a move that does not cross the play
//                           leaves it where it was: the error depends on the history of moves,
//                           not only on the direction of the last one
//   gravity_backlash        joint `joint`'s play, held against one flank by gravity wherever
//                           its torque (masses spread as above) exceeds the friction's hold, a
//                           `hold` share (default 0.15) of the largest torque the run puts on
//                           it; below that the joint stays where its last move left it. The
//                           library's backlash is held either by the move or by gravity
//   gear_harmonics          three harmonics (default 1, 3, 7 cycles per turn) of joint `joint`
//                           with fixed phases, where the library fits harmonics 1 and 2
//   warmup                  the arm grows as 1 - exp(-t / tau) over the run (sample times)
//   camera_bump             (outside the library) camera `camera` is knocked at the middle of
//                           the run and sits `magnitude` mm off along `direction` afterwards
//   lens_distortion         camera `camera`'s lens distorts where its pose estimator's
//                           calibration says it does not, in OpenCV's model with k3 and a thin
//                           prism (Weng, Cohen & Herniou 1992), beyond the library's k1, k2, p1,
//                           p2 (camera_intrinsics): k1 = magnitude, (k2, p1, p2) = `lens_shape`
//                           and (k3, s1, s3) = `lens_beyond` times magnitude (defaults -0.4, 0.2,
//                           -0.1 and 0, 0.1, -0.1; normalized image coordinates: k3 is 0, chosen
//                           when the UR3 suite cell's cam2 saw boards out to a normalized radius
//                           of 4.6, where r^6 would have been the whole lens). A board's
//                           centre is seen along the distorted ray and at the size the
//                           distortion's local stretch gives it, so PnP puts it at depth
//                           Z / sqrt(det J), J the distortion map's Jacobian there (with k1
//                           alone, the library's radial form to first order: Z (1 - 2 k1 r^2)),
//                           and turned about the ray by the map's local rotation
//                           (J21 - J12) / 2, which only the prism gives (without it J is
//                           symmetric and the board is not turned)
//
// `magnitude` is the one scale a test sets (rad, 1, or mm); everything else is shape.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/cell/disturbance.h"
#include "cellmetry/formats/config_node.h"

namespace cellmetry {

struct ConcealedPhysics : Disturbance {
  std::string kind;
  std::string robot;  // empty: every robot
  int joint = 0;      // 0-based
  std::string camera;
  double magnitude = 0.0;
  std::vector<double> link_masses_kg;  // distributed_compliance (default 1 kg per link)
  double stiffening = 0.3;
  double hold = 0.15;  // gravity_backlash: friction, as a share of max torque
  std::vector<int> harmonics = {1, 3, 7};
  double time_constant_s = 1200.0;
  Eigen::Vector3d direction = Eigen::Vector3d(0.6, 0.0, 0.8);     // camera_bump, camera axes
  Eigen::Vector3d lens_shape = Eigen::Vector3d(-0.4, 0.2, -0.1);  // lens_distortion: k2, p1, p2
  Eigen::Vector3d lens_beyond = Eigen::Vector3d(0.0, 0.1, -0.1);  // and k3, s1, s3

  std::string name() const override { return kind; }
  double size() const override { return magnitude; }
  bool ActsOn(const std::string& r) const override { return robot.empty() || robot == r; }
  std::string camera_name() const override { return camera; }
  std::vector<DisturbanceAction> Actions(const Recording& recording,
                                         const std::vector<SampleFacts>& facts,
                                         const Eigen::Vector3d& gravity_base) const override;
  void MeasureInCamera(const std::string& camera, Pose* T_cam_target) const override;
};

// {kind: ..., robot: ur3, joint: 2 (1-based), camera: cam1, magnitude: ..., <shape options>}
ConcealedPhysics ReadConcealedPhysics(const ConfigNode& node);

// The same, as the simulation reader takes it (workcell_simulation.h).
std::shared_ptr<const Disturbance> ReadConcealedDisturbance(const ConfigNode& node);

}  // namespace cellmetry
