// UrdfModel's non-template parts (urdf_model.h): the parameters, the joint frames, the chain.
#include "urdf_model.h"

#include <sstream>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/exact_number.h"
#include "urdf_conventions.h"

namespace cellmetry::urdf_robot {

namespace {

// A fixed turn taking z to `axis` (unit): joint frames with z along the axis, as
// RobotModel::JointFrames and SerialChain want them.
Pose ZToAxis(const Eigen::Vector3d& axis) {
  return Pose{Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix(),
              Eigen::Vector3d::Zero()};
}

}  // namespace

UrdfModel::UrdfModel(UrdfChain chain) : chain_(std::move(chain)) {
  const std::vector<std::string> conventions = HeldByConvention(chain_);
  for (const UrdfJoint& joint : chain_.joints) {
    const std::string j = joint.name + ".";
    const char* in_parent = " of <origin xyz>, in the parent link";
    const char* turn = " of a small turn after <origin rpy>, in the joint frame";
    parameters_.push_back(
        {j + "x", "mm", joint.xyz_mm.x(), true, {}, {}, {}, std::string("x") + in_parent, {}});
    parameters_.push_back(
        {j + "y", "mm", joint.xyz_mm.y(), true, {}, {}, {}, std::string("y") + in_parent, {}});
    parameters_.push_back(
        {j + "z", "mm", joint.xyz_mm.z(), true, {}, {}, {}, std::string("z") + in_parent, {}});
    parameters_.push_back(
        {j + "roll", "rad", 0.0, true, {}, {}, {}, std::string("roll (about x)") + turn, {}});
    parameters_.push_back(
        {j + "pitch", "rad", 0.0, true, {}, {}, {}, std::string("pitch (about y)") + turn, {}});
    parameters_.push_back(
        {j + "yaw", "rad", 0.0, true, {}, {}, {}, std::string("yaw (about z)") + turn, {}});
    parameters_.push_back(
        {j + "offset", "rad", 0.0, true, {}, {}, {}, "joint zero offset added to the reading", {}});
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

bool UrdfModel::AsNamedChain(const double* params, NamedChain* chain) const {
  chain->base_link = chain_.base_link;
  chain->tip_link = chain_.tip_link;
  chain->joints.clear();
  for (const UrdfPathJoint& read : chain_.path) {
    NamedJoint joint;
    joint.name = read.name;
    joint.parent_link = read.parent_link;
    joint.child_link = read.child_link;
    joint.T_parent_child = read.origin;
    if (read.movable >= 0) {
      const UrdfJoint& j = chain_.joints[static_cast<size_t>(read.movable)];
      const double* p = params + kParamsPerJoint * read.movable;
      joint.movable = true;
      joint.axis = j.axis;
      joint.limit = read.limit;
      joint.T_parent_child.t = Eigen::Vector3d(p[kX], p[kY], p[kZ]);
      joint.T_parent_child.R = j.R_parent_joint * RollPitchYaw(p[kRoll], p[kPitch], p[kYaw]) *
                               TurnAbout(j.axis, p[kOffset]);
    }
    chain->joints.push_back(joint);
  }
  return true;
}

bool UrdfModel::SetNominal(const std::string& name, double value) {
  const int index = FindParameter(parameters_, name);
  if (index < 0) return false;
  parameters_[static_cast<size_t>(index)].nominal = value;
  return true;
}

std::string UrdfModel::CalibratedConfig(const ConfigNode& config, const double* params) const {
  std::ostringstream out;
  out << "type: urdf\n";
  CopyTextEntry(config, "name", out);
  CopyTextEntry(config, "description", out);
  YAML::Emitter file;
  file << chain_.file;
  out << "file: " << file.c_str() << "   # the URDF the calibration ran on, unchanged\n";
  CopyTextEntry(config, "base_link", out);
  CopyTextEntry(config, "tip_link", out);
  out << "calibrated:   # replace the URDF's joint origins (mm) and zero turns and offsets (rad)\n";
  for (size_t k = 0; k < parameters_.size(); ++k) {
    YAML::Emitter name;
    name << parameters_[k].name;
    out << "  " << name.c_str() << ": " << ExactNumber(params[k]) << "\n";
  }
  return out.str();
}

}  // namespace cellmetry::urdf_robot
