// A file's `units:` key (units.h): mm or m, rad or deg, as factors to mm and rad.
#include "cellmetry/formats/units.h"

#include <cmath>

namespace cellmetry {

Units ReadUnits(const ConfigNode& node) {
  node.ExpectKeys({"length", "angle"});
  Units units;
  const std::string length = node.GetString("length", "mm");
  const std::string angle = node.GetString("angle", "rad");
  if (length == "m") {
    units.to_mm = 1000.0;
  } else if (length != "mm") {
    throw node["length"].Error("unknown length unit '" + length + "'", "Use mm or m");
  }
  if (angle == "deg") {
    units.to_rad = M_PI / 180.0;
  } else if (angle != "rad") {
    throw node["angle"].Error("unknown angle unit '" + angle + "'", "Use rad or deg");
  }
  return units;
}

Units ReadOptionalUnits(const ConfigNode& root) {
  return root.Has("units") ? ReadUnits(root["units"]) : Units();
}

}  // namespace cellmetry
