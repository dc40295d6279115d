// What effects (effect.h) may depend on, sample by sample: the facts a recording and a robot's
// nominal geometry give, gathered once before any fit.
//
//   approach      per joint, the sign of its last move into the sample's pose, in capture order
//                 (samples.csv order); repeated captures of a pose keep the sign they came with;
//                 0 until the joint first moves
//   joint frames  RobotModel::JointFrames at the nominal parameters (gravity torques)
//   links         RobotModel::ParallelLinks at the nominal parameters (delta rods)
//   flange Jacobian  without joint frames: the flange position's derivative in the joint
//                 readings (central differences of Forward at the nominal parameters), for the
//                 gravity torques of a load at the flange
//   time, temperature, payload   from samples.csv when recorded
#pragma once

#include <string>
#include <vector>

#include "cellmetry/formats/recording.h"
#include "cellmetry/model/effect.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

struct SampleFacts {
  std::vector<double> q;
  std::vector<int> approach;
  std::vector<Pose> T_base_joint;       // empty when the model has no joint frames
  std::vector<ParallelLink> links;      // empty for serial arms
  Eigen::Matrix3Xd flange_jacobian_mm;  // without joint frames: d p_flange / d q (mm/rad)
  double time_s = NAN;
  double temperature_c = NAN;
  double payload_kg = 0.0;
};

// Facts of every sample of `robot`, indexed like recording.samples (other robots' samples stay
// empty).
std::vector<SampleFacts> GatherSampleFacts(const Recording& recording, const std::string& robot,
                                           const RobotModel& model,
                                           const std::vector<double>& nominal_params);

// The geometric facts at joint readings `q` alone (q, joint frames or the flange Jacobian,
// links, at `nominal_params`); approach, time, temperature and payload are left for the caller.
// GatherSampleFacts fills each sample's with it; compensation, each command's.
SampleFacts GeometricFacts(const RobotModel& model, const std::vector<double>& nominal_params,
                           const std::vector<double>& q);

// The context an effect sees for one sample (pointers into `facts`, which must outlive it).
EffectContext ContextOf(const SampleFacts& facts, const Eigen::Vector3d& gravity_base,
                        const std::string& camera = "");

// What a recording lacks for an effect, in words ("both approach directions"); empty when
// nothing is missing.
std::string MissingFacts(const EffectNeeds& needs, const std::vector<SampleFacts>& facts);

}  // namespace cellmetry
