// Disturbance: something a simulation does to its recording that is not one of the effect
// library's equations — a spring that stiffens, a camera knocked mid-run, an arm warming up — so
// that the physics finder can be tested against the world rather than against the formula it
// fits.
//
// The simulator (workcell_simulation.h) applies what each disturbance says per sample: joint
// errors, a growth of the flange distance, a shift of what one camera measures; and per
// observation what a camera's own optics do to its measured pose (MeasureInCamera). Which
// disturbances exist is not the core's business: the experiments library provides them
// (experiments/concealed_physics.h) and hands the simulation reader a DisturbanceReader for the
// spec's `concealed:` entries.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/model/effect_context.h"

namespace cellmetry {

// What a disturbance does to one sample.
struct DisturbanceAction {
  std::vector<double> dq;                          // joint errors, rad (empty: none)
  double flange_scale = 0.0;                       // relative growth of the flange distance
  std::optional<Eigen::Vector3d> camera_shift_mm;  // added to what camera_name() measures
};

class Disturbance {
 public:
  virtual ~Disturbance() = default;

  // Its kind and size; truth.yaml records them as concealed.<name>.magnitude.
  virtual std::string name() const = 0;
  virtual double size() const = 0;
  // Whether its joint and flange actions apply to `robot`'s samples.
  virtual bool ActsOn(const std::string& robot) const = 0;
  // The camera whose measurements camera_shift_mm moves ("" for none).
  virtual std::string camera_name() const = 0;

  // One action per sample of `recording`, in capture order (stateful kinds walk the history).
  // `facts` as GatherSampleFacts gives them at the true geometry.
  virtual std::vector<DisturbanceAction> Actions(const Recording& recording,
                                                 const std::vector<SampleFacts>& facts,
                                                 const Eigen::Vector3d& gravity_base) const = 0;

  // What `camera`'s pose estimator makes of a target at `T_cam_target` (its true pose, after
  // the library's measurement effects) where this disturbance is in the camera itself: a lens
  // the estimator's calibration describes wrongly, say. Called for every observation of every
  // robot's samples; by default it changes nothing.
  virtual void MeasureInCamera(const std::string& camera, Pose* T_cam_target) const {
    (void)camera;
    (void)T_cam_target;
  }
};

// Builds a disturbance from one `concealed:` entry; raises InputError at the node.
using DisturbanceReader = std::function<std::shared_ptr<const Disturbance>(const ConfigNode& node)>;

}  // namespace cellmetry
