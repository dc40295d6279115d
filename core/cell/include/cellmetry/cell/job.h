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

#include "cellmetry/cell/held_out_setup.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/formats/config_fields.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/model/frame_block.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct WorkcellJob {
  std::string file;
  std::string kind;       // "workcell" or "homing" (homing.h reads `homing:`)
  std::string recording;  // folder, absolute or relative to the working directory
  std::optional<std::string> validation_recording;  // fresh poses to score the result on
  // The same robot in another setup: frames registered again, the rest scored (held_out_setup.h).
  std::optional<HeldOutSetupSpec> held_out_setup;
  SourceLocation held_out_setup_where;
  std::string output;  // result folder
  WorkcellProblem problem;
  std::string solver_type;
  std::optional<ConfigNode> solver_config;
  std::optional<ConfigNode> homing;  // the `homing:` section, read by homing_job.h
  // Where the job names each robot, tool target and the world target, for errors found later
  // against the recording. Keys: "world_target", "robots.<robot>", "robots.<robot>.tools.<target>".
  std::map<std::string, SourceLocation> locations;

  SourceLocation Where(const std::string& key) const;
};

// `recording_must_exist`: false when the caller supplies the recording itself (the physics
// suite simulates one per run); the job's `recording:` is then only resolved.
WorkcellJob LoadWorkcellJob(const std::string& path, Registry& registry,
                            bool recording_must_exist = true);

// Checks that the job's robots, joint counts and targets exist in the recording as the job
// expects; raises InputError naming the job file otherwise.
void ValidateJobAgainstRecording(const WorkcellJob& job, const Recording& recording);

}  // namespace cellmetry
