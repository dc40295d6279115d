// The options both dot detectors share, read from a detector's YAML node and documented once.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/camera_file.h"
#include "cellmetry/registry/registry.h"
#include "dot_common/dot_finder.h"

namespace cellmetry::dot {

// The keys ReadDotFinderOptions and ReadOptionalCamera read.
std::vector<std::string> DotFinderKeys();
std::vector<OptionDoc> DotFinderOptionDocs();

// InputError naming the key and what to give for a value out of range.
DotFinderOptions ReadDotFinderOptions(const ConfigNode& config);

// The `camera:` calibration file (camera.h ReadCamera), relative to the config's folder.
std::optional<PinholeCamera> ReadOptionalCamera(const ConfigNode& config);

// A positive length option (mm).
double ReadPositive(const ConfigNode& config, const std::string& key, double fallback,
                    const std::string& hint);

}  // namespace cellmetry::dot
