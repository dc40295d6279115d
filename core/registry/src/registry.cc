// The plugin registry (registry.h): factories by `type:` name (an unknown one gets a "did you
// mean" and the known names), and plugin libraries loaded with dlopen from the search folders.
#include "cellmetry/registry/registry.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

template <typename Map>
std::string KnownNames(const Map& factories) {
  std::string names;
  for (const auto& [name, factory] : factories) names += (names.empty() ? "" : ", ") + name;
  return names.empty() ? "(none loaded; check the plugin folder)" : names;
}

template <typename Map>
const typename Map::mapped_type& Find(const Map& factories, const std::string& kind,
                                      const std::string& type, const ConfigNode& config) {
  const auto it = factories.find(type);
  if (it != factories.end()) return it->second;
  std::vector<std::string> names;
  for (const auto& [name, factory] : factories) names.push_back(name);
  const std::string nearest = NearestWord(type, names);
  // Point at the `type:` line itself when the block has one.
  const ConfigNode where = config.IsMap() && config.Has("type") ? config["type"] : config;
  throw where.Error("unknown " + kind + " type '" + type + "'",
                    (nearest.empty() ? "" : "Did you mean '" + nearest + "'? ") + "Known " + kind +
                        " types: " + KnownNames(factories));
}

}  // namespace

std::string KindName(PluginKind kind) {
  switch (kind) {
    case PluginKind::kDetector: return "detector";
    case PluginKind::kRobotModel: return "robot model";
    case PluginKind::kSolver: return "solver";
    case PluginKind::kEffect: return "effect";
  }
  return "?";
}

Registry& Registry::Global() {
  static Registry registry;
  return registry;
}

void Registry::AddInfo(PluginInfo info) {
  for (const auto& existing : infos_) {
    if (existing.kind == info.kind && existing.name == info.name) {
      throw InputError(
          {loading_library_, 0, 0},
          KindName(info.kind) + " '" + info.name + "' is already registered by " + existing.library,
          "Remove one of the two plugin libraries from the plugin path");
    }
  }
  info.library = loading_library_.empty() ? "(built in)" : loading_library_;
  infos_.push_back(std::move(info));
}

void Registry::AddRobotModel(PluginInfo info, RobotModelFactory factory) {
  info.kind = PluginKind::kRobotModel;
  robot_models_[info.name] = std::move(factory);
  AddInfo(std::move(info));
}

void Registry::AddSolver(PluginInfo info, SolverFactory factory) {
  info.kind = PluginKind::kSolver;
  solvers_[info.name] = std::move(factory);
  AddInfo(std::move(info));
}

void Registry::AddDetector(PluginInfo info, DetectorFactory factory) {
  info.kind = PluginKind::kDetector;
  detectors_[info.name] = std::move(factory);
  AddInfo(std::move(info));
}

void Registry::AddEffect(PluginInfo info, EffectFactory factory) {
  info.kind = PluginKind::kEffect;
  effects_[info.name] = std::move(factory);
  AddInfo(std::move(info));
}

void Registry::AddCandidateOffer(CandidateOffer offer) {
  candidate_offers_.push_back(std::move(offer));
}

std::unique_ptr<Effect> Registry::CreateEffect(const std::string& type, const ConfigNode& config,
                                               const RobotModel& robot) const {
  return Find(effects_, "effect", type, config)(config, robot);
}

std::unique_ptr<Detector> Registry::CreateDetector(const std::string& type,
                                                   const ConfigNode& config) const {
  return Find(detectors_, "detector", type, config)(config);
}

std::unique_ptr<RobotModel> Registry::CreateRobotModel(const std::string& type,
                                                       const ConfigNode& config) const {
  return Find(robot_models_, "robot model", type, config)(config);
}

std::unique_ptr<Solver> Registry::CreateSolver(const std::string& type,
                                               const ConfigNode& config) const {
  return Find(solvers_, "solver", type, config)(config);
}

std::vector<PluginInfo> Registry::List() const {
  std::vector<PluginInfo> sorted = infos_;
  std::sort(sorted.begin(), sorted.end(), [](const PluginInfo& a, const PluginInfo& b) {
    return std::tie(a.kind, a.name) < std::tie(b.kind, b.name);
  });
  return sorted;
}

std::vector<std::string> Registry::Names(PluginKind kind) const {
  std::vector<std::string> names;
  for (const auto& info : List()) {
    if (info.kind == kind) names.push_back(info.name);
  }
  return names;
}

void Registry::LoadLibrary(const std::string& path) {
  std::error_code ec;
  const std::string canonical = fs::weakly_canonical(path, ec).string();
  if (loaded_libraries_.count(canonical)) return;
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    throw InputError({path, 0, 0}, std::string("cannot load plugin: ") + dlerror(),
                     "Rebuild the plugin against this cellmetry, or remove it from the path");
  }
  using AbiFn = int (*)();
  using RegisterFn = void (*)(Registry*);
  const auto abi = reinterpret_cast<AbiFn>(dlsym(handle, "cellmetry_plugin_abi_version"));
  const auto entry = reinterpret_cast<RegisterFn>(dlsym(handle, "cellmetry_register_plugin"));
  if (!abi || !entry) {
    throw InputError({path, 0, 0}, "not a cellmetry plugin (no CELLMETRY_PLUGIN_ENTRY)",
                     "Remove the file from the plugin folder");
  }
  if (abi() != kPluginAbiVersion) {
    throw InputError({path, 0, 0},
                     "plugin built for plugin ABI " + std::to_string(abi()) +
                         ", this cellmetry has " + std::to_string(kPluginAbiVersion),
                     "Rebuild the plugin against the installed cellmetry headers");
  }
  loaded_libraries_.insert(canonical);
  loading_library_ = path;
  try {
    entry(this);
  } catch (...) {
    loading_library_.clear();
    throw;
  }
  loading_library_.clear();
}

void Registry::LoadFolder(const std::string& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  std::vector<std::string> libraries;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".so" && name.rfind("lib", 0) == 0) {
      libraries.push_back(entry.path().string());
    }
  }
  std::sort(libraries.begin(), libraries.end());  // deterministic order
  for (const auto& library : libraries) LoadLibrary(library);
}

void Registry::LoadDefaultFolders(const std::string& executable_path) {
  std::error_code ec;
  const fs::path exe = fs::weakly_canonical(executable_path, ec);
  LoadFolder((exe.parent_path() / "plugins").string());
  LoadFolder((exe.parent_path() / ".." / "lib" / "cellmetry" / "plugins").string());
  if (const char* env = std::getenv("CELLMETRY_PLUGIN_PATH")) {
    std::stringstream paths(env);
    std::string folder;
    while (std::getline(paths, folder, ':')) {
      if (!folder.empty()) LoadFolder(folder);
    }
  }
}

}  // namespace cellmetry
