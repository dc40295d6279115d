// Units of a file: `units: {length: mm|m, angle: rad|deg}`, converted to mm and rad on reading.
#pragma once

#include "cellmetry/formats/config_node.h"

namespace cellmetry {

struct Units {
  double to_mm = 1.0;   // multiply a length in the file's unit by this
  double to_rad = 1.0;  // multiply an angle in the file's unit by this
};

// Reads `node` (the value of a `units:` key); unknown units are InputErrors at their key.
Units ReadUnits(const ConfigNode& node);

// `root`'s `units:` key when present, mm and rad otherwise.
Units ReadOptionalUnits(const ConfigNode& root);

}  // namespace cellmetry
