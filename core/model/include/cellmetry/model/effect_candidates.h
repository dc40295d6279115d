// What an effect plugin offers the physics finder (diagnosis/diagnosis.h): its effects as
// candidates for one cell, each a config its own factory reads, with the words a report uses.
//
// The finder knows no effect by name. A plugin registers an offer (Registry::AddCandidateOffer);
// the finder calls every offer with what it may know of the cell (CandidateCell), builds each
// offered effect through the registry and tests them all. A plugin decides which of its effects
// can act on the cell (a joint's compliance on every joint, a rod pair's skew only on a parallel
// arm), names them, and says what data would make one testable.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "cellmetry/model/robot_model.h"

namespace cellmetry {

// The cell as an offer sees it.
struct CandidateCell {
  struct Robot {
    std::string name;
    const RobotModel* model = nullptr;
  };
  std::vector<Robot> robots;
  std::vector<std::string> cameras;    // the recording's, in its order
  std::vector<std::string> targets;    // the recording's, by name
  std::string world_target;            // "" when the cell has none
  bool use_tool_rotation = false;      // measured rotations of carried targets are fitted
  bool level_stated = false;           // the job states a robot standing level
  bool temperatures = false;           // some sample has a temperature
  bool times = false;                  // some sample has a time
  std::vector<double> link_masses_kg;  // the job's (empty: each model's own, or 1 kg a link)
  std::vector<int> gear_harmonics;     // of the drives beyond 1 and 2 (the job's)
  std::vector<std::array<int, 2>> joint_couplings;  // {driving, driven}, 1-based (the job's)
  // Offer too the candidates that act on every camera or target at once (one cause shared).
  bool group_candidates = false;
};

// One candidate: what diagnosis.h's CandidateEffect holds, less the effect object (the finder
// builds it from `config` through the registry).
struct OfferedCandidate {
  std::string name;       // unique in the cell: "ur3.compliance_j2", "camera.focal_cam1"
  std::string robot;      // whose chain it is in (a measurement effect: any robot of the cell)
  std::string config;     // the effect's YAML, flow style: "{type: backlash, joints: [2]}"
  std::string label;      // "joint 2 backlash"
  std::string data_hint;  // what data separates it from the geometry
  std::string family;     // candidates naming the same physics (nested forms); "" alone
  std::string group;      // candidates one cause shows as; "" alone
  std::string group_label;
  std::vector<std::string> atoms;  // what it shares with a candidate it is nested in
  bool frame = false;              // a frame the job's statements determine (diagnosis.h)
};

using CandidateOffer = std::function<std::vector<OfferedCandidate>(const CandidateCell& cell)>;

}  // namespace cellmetry
