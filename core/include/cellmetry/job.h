// Job: a YAML file that says what to identify, from which recording, with which solver.
//
// See docs/formats.md for every key. Reading a job loads the plugin folders it names, builds
// the robot models it names (through the registry), and checks every key, so a job that loads
// runs: unknown keys, wrong types, missing files and unknown plugin types are InputErrors with
// file:line:column.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>

#include "cellmetry/config_node.h"
#include "cellmetry/recording.h"
#include "cellmetry/registry.h"
#include "cellmetry/workcell_problem.h"

namespace cellmetry {

struct WorkcellJob {
  std::string file;
  std::string recording;       // folder, absolute or relative to the working directory
  std::string output;          // result folder
  WorkcellProblem problem;
  std::string solver_type;
  std::optional<ConfigNode> solver_config;
  // Where the job names each robot, tool target and the world target, for errors found later
  // against the recording. Keys: "world_target", "robots.<robot>", "robots.<robot>.tools.<target>".
  std::map<std::string, SourceLocation> locations;

  SourceLocation Where(const std::string& key) const;
};

// `recording_must_exist`: false when the caller supplies the recording itself (the physics
// suite simulates one per run); the job's `recording:` is then only resolved.
WorkcellJob LoadWorkcellJob(const std::string& path, Registry& registry,
                            bool recording_must_exist = true);

// The `job:` kind of a job file ("workcell", "kinematic", "homing").
std::string JobKind(const std::string& path);

// Helpers shared by every job kind.
Pose ReadPose(const ConfigNode& node);  // {xyz: [mm], rvec: [rad]}, both optional
// `free: [x, y, z, rx, ry, rz] | all | none`, or `fallback` without the key.
std::array<bool, 6> ReadFreeFlags(const ConfigNode& node, std::array<bool, 6> fallback);
// A recording folder named at `node`, resolved against the job file; InputError there if absent.
std::string ReadRecordingPath(const ConfigNode& node);

// Checks that the job's robots, joint counts and targets exist in the recording as the job
// expects; raises InputError naming the job file otherwise.
void ValidateJobAgainstRecording(const WorkcellJob& job, const Recording& recording);

}  // namespace cellmetry
