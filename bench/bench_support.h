// Helpers shared by the benchmark targets.
#pragma once

#include <memory>
#include <string>

#include "cellmetry/basics/progress.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry::bench {

// The registry with this build's plugins loaded (once), progress quiet.
inline Registry& Plugins() {
  static const bool loaded = [] {
    Progress::SetQuiet(true);
    Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  return Registry::Global();
}

// A file of the source tree, e.g. Source("configs/jobs/ur3_diagnose.yaml").
inline std::string Source(const std::string& relative) {
  return std::string(CELLMETRY_SOURCE_DIR) + "/" + relative;
}

// A detector from its YAML block.
inline std::unique_ptr<Detector> MakeDetector(const std::string& yaml) {
  const ConfigNode config = ConfigNode::LoadString(yaml, "bench");
  return Plugins().CreateDetector(config["type"].AsString(), config);
}

}  // namespace cellmetry::bench
