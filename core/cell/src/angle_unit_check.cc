// CheckAngleUnits (angle_unit_check.h): the target's turns between captures against the
// nominal flange's, as declared and with each file's angles read otherwise.
#include "angle_unit_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <tuple>
#include <vector>

#include "cellmetry/basics/euler_angles.h"
#include "cellmetry/basics/statistics.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"

namespace cellmetry {
namespace {

constexpr double kDegPerRad = 180.0 / M_PI;
constexpr size_t kMaxCaptures = 120;  // spread over the run: 7,140 pairs, plenty

// One capture of a carried target with its rotation: the sample's joints and the measured
// rotation (as read, rad).
struct Capture {
  const Sample* sample;
  Eigen::Vector3d rvec;
};

// How a recording's numbers are read: its joint readings scaled by `joint_scale`, its measured
// rotations by `rotation` (from the rotation vector as read), the robot config's angles scaled by
// `model_scale`.
struct Reading {
  double joint_scale = 1.0;
  double model_scale = 1.0;
  std::function<Eigen::Matrix3d(const Eigen::Vector3d&)> rotation = [](const Eigen::Vector3d& r) {
    return RotationFromRvec(r.data());
  };
};

// The captures of `target` by `camera` with a rotation, on `robot`, at most kMaxCaptures spread
// over the whole run.
std::vector<Capture> CapturesOf(const WorkcellRobot& robot, const std::string& target,
                                const std::string& camera, const Recording& recording) {
  std::vector<Capture> captures;
  for (const Observation& o : recording.observations) {
    if (o.target != target || o.camera != camera || !o.rvec) continue;
    const int index = recording.SampleIndex(o.sample);
    if (index < 0) continue;
    const Sample& s = recording.samples[index];
    if (s.robot != robot.name || static_cast<int>(s.q.size()) != robot.model->num_joints()) {
      continue;
    }
    captures.push_back({&s, *o.rvec});
  }
  if (captures.size() <= kMaxCaptures) return captures;
  std::vector<Capture> spread;
  for (size_t k = 0; k < kMaxCaptures; ++k) {
    spread.push_back(captures[k * captures.size() / kMaxCaptures]);
  }
  return spread;
}

// The rotation between two rotation matrices, in the first one's frame: its angle (rad) and
// axis.
struct Turn {
  double angle = 0.0;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
};
Turn TurnBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const Eigen::AngleAxisd turn(a.transpose() * b);
  return {turn.angle(), turn.axis()};
}

double AngleBetween(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

// How far the target's turns between captures are from the flange's, as a share: the larger of
// two. (1) Over the quarter of the pairs of captures whose target turns most (in the others a
// pose estimator's rotation noise weighs more than the turn), the median of |target's angle -
// flange's angle| as a share of their median angle: a share, since reading angles in another
// unit scales every turn. (2) Over pairs of those turns, the median of |the angle between the
// target's two axes - the angle between the flange's two| as a share of a right angle: the axes
// are the flange's turned by the fixed tool rotation, so the angles between them agree too,
// where a quaternion's columns read in another order keep every turn's angle (a permutation of
// a quaternion's coordinates keeps their dot products) but not its axis. Negative where the
// model has no pose for some capture or the target does not turn.
double TurnMismatch(const WorkcellRobot& robot, const std::vector<Capture>& captures,
                    const Reading& reading) {
  std::vector<double> params;
  for (const Parameter& p : robot.model_parameters) {
    params.push_back(p.unit == "rad" ? p.nominal * reading.model_scale : p.nominal);
  }
  std::vector<Eigen::Matrix3d> target, flange;
  for (const Capture& c : captures) {
    std::vector<double> q = c.sample->q;
    for (double& v : q) v *= reading.joint_scale;
    Pose T_base_flange;
    if (!robot.model->Forward(q.data(), params.data(), &T_base_flange)) return -1.0;
    target.push_back(reading.rotation(c.rvec));
    flange.push_back(T_base_flange.R);
  }
  std::vector<std::pair<Turn, Turn>> turns;  // (target's, flange's) per pair of captures
  for (size_t i = 0; i < captures.size(); ++i) {
    for (size_t j = i + 1; j < captures.size(); ++j) {
      turns.push_back({TurnBetween(target[i], target[j]), TurnBetween(flange[i], flange[j])});
    }
  }
  std::sort(turns.begin(), turns.end(),
            [](const auto& a, const auto& b) { return a.first.angle > b.first.angle; });
  turns.resize(turns.size() / 4);
  std::vector<double> mismatch, turned, axes;
  for (const auto& [t, f] : turns) {
    mismatch.push_back(std::abs(t.angle - f.angle));
    turned.push_back(t.angle);
  }
  if (turned.empty() || !(Median(turned) > 0)) return -1.0;
  for (size_t k = 0; k + 1 < turns.size() && axes.size() < 5000; ++k) {
    const auto& [t1, f1] = turns[k];
    const auto& [t2, f2] = turns[k + 1];
    axes.push_back(std::abs(AngleBetween(t1.axis, t2.axis) - AngleBetween(f1.axis, f2.axis)));
  }
  return std::max(Median(mismatch) / Median(turned), axes.empty() ? 0.0 : Median(axes) / M_PI_2);
}

// Where `file` says its angle unit and what it says ("" when it says none).
SourceLocation DeclaredAngle(const std::string& file, std::string* unit) {
  unit->clear();
  if (file.empty() || !std::filesystem::is_regular_file(file)) return {file, 0, 0};
  try {
    const ConfigNode root = ConfigNode::LoadFile(file);
    if (!root.Has("units")) return {file, 0, 0};
    const ConfigNode units = root["units"];
    if (!units.Has("angle")) return units.location();
    *unit = units["angle"].AsString();
    return units["angle"].location();
  } catch (const InputError&) {
    return {file, 0, 0};
  }
}

// How an imported recording's mapping (its copy, <recording>/import.yaml) read the rotations of
// one target in one camera: the rotation's `convention`, `order` and `axes` as written there
// (empty when absent), where each is, and whether the rotation was inverted on import
// (pose_of: camera_in_target). Empty when the recording was not imported.
struct DeclaredRotation {
  std::string convention, order, axes;
  SourceLocation convention_at, order_at, axes_at;
  bool inverted = false;
};

// Whether a mapping's camera: or target: names `name`: by name, or by a column (any row may).
bool Names(const ConfigNode& node, const std::string& name) {
  return node.IsMap() || (node.IsScalar() && node.AsString() == name);
}

DeclaredRotation DeclaredRotationOf(const Recording& recording, const std::string& camera,
                                    const std::string& target) {
  const std::string file = recording.folder + "/import.yaml";
  if (recording.folder.empty() || !std::filesystem::is_regular_file(file)) return {};
  try {
    const ConfigNode root = ConfigNode::LoadFile(file);
    if (!root.Has("observations")) return {};
    for (const ConfigNode& o : root["observations"].Elements()) {
      if (!o.Has("camera") || !o.Has("target") || !Names(o["camera"], camera) ||
          !Names(o["target"], target) || !o.Has("rotation")) {
        continue;
      }
      const ConfigNode rotation = o["rotation"];
      DeclaredRotation declared;
      declared.inverted = o.GetString("pose_of", "") == "camera_in_target";
      for (auto [key, text, at] :
           {std::tuple{"convention", &declared.convention, &declared.convention_at},
            std::tuple{"order", &declared.order, &declared.order_at},
            std::tuple{"axes", &declared.axes, &declared.axes_at}}) {
        if (!rotation.Has(key)) continue;
        *text = rotation[key].AsString();
        *at = rotation[key].location();
      }
      return declared;
    }
  } catch (const InputError&) {
  }
  return {};
}

std::string Percent(double share) {
  char text[32];
  if (share < 0.1) {
    std::snprintf(text, sizeof text, "%.1f %%", 100.0 * share);
  } else {
    std::snprintf(text, sizeof text, "%.0f %%", 100.0 * share);
  }
  return text;
}

// The file's angles read in the other unit: a factor on what was read, and that unit's name.
double OtherScale(const std::string& declared) {
  return declared == "deg" ? kDegPerRad : 1.0 / kDegPerRad;
}
std::string OtherUnit(const std::string& declared) {
  return OtherScale(declared) > 1.0 ? "rad" : "deg";
}

// The recording's rotations as read had the table's rotation been read otherwise: `reread`
// takes the rotation the table's numbers were read as (before any inversion on import) to the
// one they would have been read as.
Reading TableReadOtherwise(std::function<Eigen::Matrix3d(const Eigen::Matrix3d&)> reread,
                           bool inverted) {
  Reading reading;
  reading.rotation = [reread = std::move(reread), inverted](const Eigen::Vector3d& rvec) {
    const Eigen::Matrix3d read = RotationFromRvec(rvec.data());
    const Eigen::Matrix3d other = reread(inverted ? Eigen::Matrix3d(read.transpose()) : read);
    return inverted ? Eigen::Matrix3d(other.transpose()) : other;
  };
  return reading;
}

// The mapping's quaternion columns in the other order: the columns are recovered from the
// rotation read (up to a sign, which is the same rotation) and put in their places.
Reading OtherQuaternionOrder(bool scalar_first, bool inverted) {
  return TableReadOtherwise(
      [scalar_first](const Eigen::Matrix3d& R) {
        const Eigen::Quaterniond read(R);
        // Read as (w, x, y, z) = (c0, c1, c2, c3), the columns were (x, y, z, w); or the reverse.
        const Eigen::Quaterniond other =
            scalar_first ? Eigen::Quaterniond(read.z(), read.w(), read.x(), read.y())
                         : Eigen::Quaterniond(read.x(), read.y(), read.z(), read.w());
        return Eigen::Matrix3d(other.normalized().toRotationMatrix());
      },
      inverted);
}

// The mapping's Euler angles about `axes` in the other convention (intrinsic for extrinsic, or
// the reverse): the angles are recovered from the rotation read and turned the other way. Either
// branch of the angles gives the same rotation the other way too.
Reading OtherEulerConvention(const std::array<int, 3>& axes, bool intrinsic, bool inverted) {
  return TableReadOtherwise(
      [axes, intrinsic](const Eigen::Matrix3d& R) {
        return EulerToRotation(axes, !intrinsic, RotationToEuler(axes, intrinsic, R));
      },
      inverted);
}

[[noreturn]] void Refuse(const SourceLocation& where, const std::string& what_was_read,
                         const std::string& as_declared_text, const std::string& other_text,
                         const WorkcellRobot& robot, const std::string& target,
                         const std::string& camera, double as_declared, double as_other,
                         const std::string& hint) {
  throw InputError(where,
                   "robot " + robot.name + " turns its flange unlike target '" + target +
                       "' turns in " + camera +
                       " between captures (their angles and axes, "
                       "median): " +
                       Percent(as_declared) + " apart with " + what_was_read + " " +
                       as_declared_text + ", " + Percent(as_other) + " " + other_text,
                   hint);
}

// The imported table's rotations read in the other quaternion order or Euler convention than
// the mapping declares, refused at the mapping's line when that agrees kAngleBetterFactor times
// better than the declaration.
void TryOtherTableReadings(const Recording& recording, const WorkcellRobot& robot,
                           const std::string& target, const std::string& camera,
                           const std::vector<Capture>& captures, double as_declared) {
  const DeclaredRotation declared = DeclaredRotationOf(recording, camera, target);
  const bool quaternion =
      declared.convention == "quaternion" && (declared.order == "wxyz" || declared.order == "xyzw");
  const auto euler_axes = ParseEulerOrder(declared.order);
  const bool euler = declared.convention == "euler" && euler_axes &&
                     (declared.axes == "intrinsic" || declared.axes == "extrinsic");
  const bool rpy = declared.convention == "rpy";
  if (!quaternion && !euler && !rpy) return;
  const bool intrinsic = euler && declared.axes == "intrinsic";
  const Reading other =
      quaternion ? OtherQuaternionOrder(declared.order == "wxyz", declared.inverted)
                 : OtherEulerConvention(euler ? *euler_axes : std::array<int, 3>{0, 1, 2},
                                        intrinsic, declared.inverted);
  const double mismatch = TurnMismatch(robot, captures, other);
  if (!(mismatch >= 0 && mismatch * kAngleBetterFactor < as_declared)) return;
  if (quaternion) {
    const std::string other_order = declared.order == "wxyz" ? "xyzw" : "wxyz";
    Refuse(declared.order_at, "the quaternion's columns read as", declared.order,
           "read as " + other_order, robot, target, camera, as_declared, mismatch,
           "The quaternion's scalar looks " +
               std::string(other_order == "wxyz" ? "first" : "last") +
               ": say order: " + other_order + " in the mapping and import it again");
  }
  if (rpy) {
    Refuse(declared.convention_at, "the angles read as", "rpy (fixed axes x, y, z)",
           "read as Euler XYZ about turned axes", robot, target, camera, as_declared, mismatch,
           "The angles look intrinsic (each turn about the turned axes): say convention: euler, "
           "order: XYZ, axes: intrinsic in the mapping and import it again");
  }
  const std::string other_axes = intrinsic ? "extrinsic" : "intrinsic";
  Refuse(declared.axes_at, "the Euler angles read as", declared.order + " " + declared.axes,
         "read as " + declared.order + " " + other_axes, robot, target, camera, as_declared,
         mismatch,
         "The Euler angles look " + other_axes + " (each turn about the " +
             (intrinsic ? "fixed" : "turned") + " axes): say axes: " + other_axes +
             " in the mapping and import it again");
}

// The alternatives to the declared reading, each refused when it agrees kAngleBetterFactor
// times better than the declaration.
void TryOtherReadings(const WorkcellJob& job, const Recording& recording,
                      const WorkcellRobot& robot, const std::string& target,
                      const std::string& camera, const std::vector<Capture>& captures,
                      double as_declared) {
  auto better = [&](double other) {
    return other >= 0 && other * kAngleBetterFactor < as_declared;
  };
  std::string unit;
  const SourceLocation in_recording =
      DeclaredAngle(recording.folder.empty() ? "" : recording.folder + "/recording.yaml", &unit);
  Reading recording_other;
  const double scale = OtherScale(unit);
  recording_other.joint_scale = scale;
  recording_other.rotation = [scale](const Eigen::Vector3d& r) {
    const Eigen::Vector3d scaled = scale * r;
    return RotationFromRvec(scaled.data());
  };
  const double other = TurnMismatch(robot, captures, recording_other);
  const std::string other_unit = OtherUnit(unit);
  const std::string looks = other_unit == "rad" ? "radians" : "degrees";
  if (better(other)) {
    Refuse(in_recording, "the recording's angles in", unit.empty() ? "rad" : unit,
           "read in " + other_unit, robot, target, camera, as_declared, other,
           "The recording's angles look like " + looks + ": declare units: {angle: " + other_unit +
               "} there, or convert its numbers");
  }
  TryOtherTableReadings(recording, robot, target, camera, captures, as_declared);
  const SourceLocation in_model = DeclaredAngle(robot.model_file, &unit);
  Reading model_other;
  model_other.model_scale = OtherScale(unit);
  const double model = TurnMismatch(robot, captures, model_other);
  if (better(model)) {
    const std::string model_unit = OtherUnit(unit);
    Refuse(in_model.file.empty() ? job.Where("robots." + robot.name) : in_model,
           "the robot config's angles in", unit.empty() ? "rad" : unit, "read in " + model_unit,
           robot, target, camera, as_declared, model,
           "The robot config's angles look like " +
               std::string(model_unit == "rad" ? "radians" : "degrees") +
               ": declare units: {angle: " + model_unit + "} there, or convert its numbers");
  }
}

}  // namespace

void CheckAngleUnits(const WorkcellJob& job, const Recording& recording) {
  for (const WorkcellRobot& robot : job.problem.robots) {
    for (const WorkcellTool& tool : robot.tools) {
      for (const auto& camera : recording.cameras) {
        const std::vector<Capture> captures = CapturesOf(robot, tool.target, camera, recording);
        if (captures.size() < 3) continue;
        const double as_declared = TurnMismatch(robot, captures, Reading{});
        if (as_declared < 0 || as_declared <= kAngleMismatchShare) continue;
        TryOtherReadings(job, recording, robot, tool.target, camera, captures, as_declared);
      }
    }
  }
}

}  // namespace cellmetry
