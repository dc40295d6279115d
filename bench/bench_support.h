// Helpers shared by the benchmark targets.
#pragma once

#include <memory>
#include <string>

#include "cellmetry/progress.h"
#include "cellmetry/registry.h"

namespace cellmetry::bench {

// A detector from its YAML block, with this build's plugins loaded (once) and progress quiet.
inline std::unique_ptr<Detector> MakeDetector(const std::string& yaml) {
  static const bool loaded = [] {
    Progress::SetQuiet(true);
    Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  const ConfigNode config = ConfigNode::LoadString(yaml, "bench");
  return Registry::Global().CreateDetector(config["type"].AsString(), config);
}

}  // namespace cellmetry::bench
