// Registry: where plugins announce themselves, and how the core finds them.
//
// A plugin is a shared library that exports one C function,
//
//   CELLMETRY_PLUGIN_ENTRY(registry) { registry->AddSolver(info, factory); ... }
//
// which the loader calls once after dlopen(). The registry maps a `type:` name from a job to a
// factory that builds the object from the rest of that YAML node. The core never names a plugin:
// it asks the registry for whatever type the job says.
//
// Search order for plugin libraries (all are loaded; a name registered twice is an error):
//   1. <folder of the executable>/plugins
//   2. each folder in $CELLMETRY_PLUGIN_PATH (colon-separated)
//   3. each folder in a job's `plugin_paths:`
//
// Memory across the plugin boundary (docs/architecture.md, "The plugin contract"): what a plugin
// allocates, the plugin frees.
//   - A factory returns its object as std::unique_ptr<Interface>. Every interface (RobotModel,
//     Solver, Detector, Effect) has a virtual destructor (checked below), so the core's delete
//     calls the plugin's own deleting destructor: the object is destroyed and freed by code in
//     the plugin, with the allocator the plugin used.
//   - Everything else that crosses is a value: PluginInfo, Parameter lists, Detection keypoints,
//     strings and Eigen matrices. They are standard-library and Eigen types allocated through
//     the process's one global operator new, so a plugin links libstdc++ dynamically (never
//     -static-libstdc++) and does not replace operator new/delete.
//   - A plugin is never unloaded (no dlclose): its factories, vtables and the objects they built
//     stay valid until the process exits.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "cellmetry/estimation/solver.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/detector.h"
#include "cellmetry/model/effect.h"
#include "cellmetry/model/effect_candidates.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

// Bumped whenever a plugin-facing header changes incompatibly; plugins built against another
// version are refused with a message saying so.
inline constexpr int kPluginAbiVersion = 9;  // 2: inverse kinematics, limits, detectors;
                                             // 3: effects, joint offsets and frames
                                             // 4: serial chains and calibrated configs (exports)
                                             // 5: flange twists (RobotModel::ForwardWithTwists)
                                             // 6: Parameter::plausible_nonnegative (its layout)
                                             // 7: Solver::LimitThreads (Solver's layout)
                                             // 8: Parameter::convention, plausible_group and
                                             //    plausible_common (its layout)
                                             // 9: effects offer diagnosis candidates
                                             //    (Registry's layout)

enum class PluginKind { kDetector, kRobotModel, kSolver, kEffect };
std::string KindName(PluginKind kind);

struct OptionDoc {
  std::string name;
  std::string unit;           // "" when unitless
  std::string default_value;  // "" when required
  std::string description;
};

struct PluginInfo {
  PluginKind kind = PluginKind::kSolver;
  std::string name;         // the `type:` a job uses
  std::string description;  // one line
  std::vector<OptionDoc> options;
  std::string library;  // filled in by the loader
};

using RobotModelFactory = std::function<std::unique_ptr<RobotModel>(const ConfigNode& config)>;
using SolverFactory = std::function<std::unique_ptr<Solver>(const ConfigNode& config)>;
// Detector factories are called once per worker thread (detector.h).
using DetectorFactory = std::function<std::unique_ptr<Detector>(const ConfigNode& config)>;
// Effect factories get the effect's YAML node and the robot model it will act on (joint count,
// parameter names), so that per-joint parameters can be named and checked.
using EffectFactory =
    std::function<std::unique_ptr<Effect>(const ConfigNode& config, const RobotModel& robot)>;

static_assert(std::has_virtual_destructor_v<RobotModel> && std::has_virtual_destructor_v<Solver> &&
                  std::has_virtual_destructor_v<Detector> && std::has_virtual_destructor_v<Effect>,
              "a plugin object must be destroyed by the plugin's own (virtual) destructor");

class Registry {
 public:
  // The process-wide registry that plugin libraries register into.
  static Registry& Global();

  void AddRobotModel(PluginInfo info, RobotModelFactory factory);
  void AddSolver(PluginInfo info, SolverFactory factory);
  void AddDetector(PluginInfo info, DetectorFactory factory);
  void AddEffect(PluginInfo info, EffectFactory factory);
  // An effect plugin's candidates for the physics finder (model/effect_candidates.h); called in
  // the order the plugins registered them.
  void AddCandidateOffer(CandidateOffer offer);
  const std::vector<CandidateOffer>& candidate_offers() const { return candidate_offers_; }

  // Build a plugin object of `type`; raise InputError at `config` naming the known types if
  // `type` is not registered.
  std::unique_ptr<RobotModel> CreateRobotModel(const std::string& type,
                                               const ConfigNode& config) const;
  std::unique_ptr<Solver> CreateSolver(const std::string& type, const ConfigNode& config) const;
  std::unique_ptr<Detector> CreateDetector(const std::string& type, const ConfigNode& config) const;
  std::unique_ptr<Effect> CreateEffect(const std::string& type, const ConfigNode& config,
                                       const RobotModel& robot) const;

  std::vector<PluginInfo> List() const;
  std::vector<std::string> Names(PluginKind kind) const;

  // Loads every lib*.so in `folder` (missing folders are ignored).
  void LoadFolder(const std::string& folder);
  // Loads one plugin library; raises InputError when it cannot be loaded or is not a plugin.
  void LoadLibrary(const std::string& path);
  // Loads from <executable folder>/plugins and $CELLMETRY_PLUGIN_PATH.
  void LoadDefaultFolders(const std::string& executable_path);

 private:
  void AddInfo(PluginInfo info);

  std::vector<PluginInfo> infos_;
  std::map<std::string, RobotModelFactory> robot_models_;
  std::map<std::string, SolverFactory> solvers_;
  std::map<std::string, DetectorFactory> detectors_;
  std::map<std::string, EffectFactory> effects_;
  std::vector<CandidateOffer> candidate_offers_;
  std::set<std::string> loaded_libraries_;
  std::string loading_library_;
};

}  // namespace cellmetry

#define CELLMETRY_PLUGIN_ENTRY(registry_arg)                                             \
  extern "C" __attribute__((visibility("default"))) int cellmetry_plugin_abi_version() { \
    return ::cellmetry::kPluginAbiVersion;                                               \
  }                                                                                      \
  extern "C" __attribute__((visibility("default"))) void cellmetry_register_plugin(      \
      ::cellmetry::Registry* registry_arg)
