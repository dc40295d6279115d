// Compensation targets (compensation/compensation_targets.h, ReadCompensationTargets): the fuzzed
// bytes as the TARGETS.csv `cellmetry compensate` reads, for a six-joint arm. What loads must be
// targets the solver can take: finite positions, a rotation that is one (orthonormal, det +1),
// six joint values or none, approach directions of -1, 0 or +1, a payload >= 0.
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "cellmetry/compensation/compensation_targets.h"
#include "fuzz_support.h"

namespace {

constexpr int kJoints = 6;

bool Usable(const cellmetry::CompensationTarget& t) {
  const Eigen::Matrix3d& R = t.R_world_tool;
  const bool rotation = R.allFinite() &&
                        (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-6 &&
                        std::abs(R.determinant() - 1.0) < 1e-6;
  bool joints = t.q_rad.empty() || static_cast<int>(t.q_rad.size()) == kJoints;
  for (const double q : t.q_rad) joints = joints && std::isfinite(q);
  bool approach = t.approach.empty() || static_cast<int>(t.approach.size()) == kJoints;
  for (const int a : t.approach) approach = approach && (a == -1 || a == 0 || a == 1);
  const bool joint_target = t.kind == cellmetry::CompensationTarget::Kind::kJoints;
  return t.p_world_tool_mm.allFinite() && rotation && joints && approach &&
         (!joint_target || !t.q_rad.empty()) && t.payload_kg >= 0 && std::isfinite(t.payload_kg);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = cellmetry::fuzz::TempDir() + "/targets.csv";
  cellmetry::fuzz::WriteFile(path, data, size);
  cellmetry::fuzz::CheckContract([&] {
    for (const auto& target : cellmetry::ReadCompensationTargets(path, kJoints)) {
      if (!Usable(target)) {
        const std::string line = std::to_string(target.line);
        cellmetry::fuzz::Violation("ReadCompensationTargets",
                                   "a target the solver cannot take loaded (line " + line + ")");
      }
    }
  });
  return 0;
}
