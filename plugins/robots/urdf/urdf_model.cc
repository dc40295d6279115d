// UrdfModel's non-template parts (urdf_model.h): the parameters, the joint frames, the chain.
#include "urdf_model.h"

#include "urdf_conventions.h"

namespace cellmetry::urdf_robot {

namespace {

// A fixed turn taking z to `axis` (unit): joint frames with z along the axis, as
// RobotModel::JointFrames and SerialChain want them.
Pose ZToAxis(const Eigen::Vector3d& axis) {
  return Pose{Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis)
                  .toRotationMatrix(),
              Eigen::Vector3d::Zero()};
}

}  // namespace

UrdfModel::UrdfModel(UrdfChain chain) : chain_(std::move(chain)) {
  const std::vector<std::string> conventions = HeldByConvention(chain_);
  for (const UrdfJoint& joint : chain_.joints) {
    const std::string j = joint.name + ".";
    const char* in_parent = " of <origin xyz>, in the parent link";
    const char* turn = " of a small turn after <origin rpy>, in the joint frame";
    parameters_.push_back({j + "x", "mm", joint.xyz_mm.x(), true, {}, {}, {},
                           std::string("x") + in_parent, {}});
    parameters_.push_back({j + "y", "mm", joint.xyz_mm.y(), true, {}, {}, {},
                           std::string("y") + in_parent, {}});
    parameters_.push_back({j + "z", "mm", joint.xyz_mm.z(), true, {}, {}, {},
                           std::string("z") + in_parent, {}});
    parameters_.push_back({j + "roll", "rad", 0.0, true, {}, {}, {},
                           std::string("roll (about x)") + turn, {}});
    parameters_.push_back({j + "pitch", "rad", 0.0, true, {}, {}, {},
                           std::string("pitch (about y)") + turn, {}});
    parameters_.push_back({j + "yaw", "rad", 0.0, true, {}, {}, {},
                           std::string("yaw (about z)") + turn, {}});
    parameters_.push_back({j + "offset", "rad", 0.0, true, {}, {}, {},
                           "joint zero offset added to the reading", {}});
  }
  for (size_t k = 0; k < parameters_.size(); ++k) parameters_[k].convention = conventions[k];
}

bool UrdfModel::JointFrames(const double* q, const double* params,
                            std::vector<Pose>* T_base_joint) const {
  T_base_joint->clear();
  Pose chain = Pose::Identity();
  for (size_t i = 0; i < chain_.joints.size(); ++i) {
    const double* p = params + kParamsPerJoint * i;
    chain = chain * JointOrigin(i, p);
    chain.R = chain.R * TurnAbout(chain_.joints[i].axis, q[i] + p[kOffset]);
    T_base_joint->push_back(chain * ZToAxis(chain_.joints[i].axis));
  }
  T_base_joint->push_back(chain * chain_.T_last_joint_tip);
  return true;
}

bool UrdfModel::AsSerialChain(const double* params, SerialChain* chain) const {
  chain->T_parent_joint.clear();
  Pose T_previous_z = Pose::Identity();  // M_{i-1}
  for (size_t i = 0; i < chain_.joints.size(); ++i) {
    const double* p = params + kParamsPerJoint * i;
    const Eigen::Vector3d& axis = chain_.joints[i].axis;
    Pose origin = JointOrigin(i, p);
    origin.R = origin.R * TurnAbout(axis, p[kOffset]);
    const Pose T_joint_z = ZToAxis(axis);
    chain->T_parent_joint.push_back(T_previous_z.inverse() * origin * T_joint_z);
    T_previous_z = T_joint_z;
  }
  chain->T_last_joint_flange = T_previous_z.inverse() * chain_.T_last_joint_tip;
  chain->not_expressible.clear();
  return true;
}

}  // namespace cellmetry::urdf_robot
