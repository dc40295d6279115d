// An observation entry's uncertainties (mapping_keys.h): the position's from columns, per row,
// as a standard deviation or an expanded uncertainty at a stated level of confidence; the
// rotation's as the instrument states it, one sigma for every row.
#include <cmath>

#include "mapping_keys.h"

namespace cellmetry::import_keys {
namespace {

// The coverage factors k of GUM (JCGM 100:2008) G.1.3, Table G.1: an expanded uncertainty
// U = k u at the level of confidence p, for a normal distribution. A standard deviation
// (level: sigma) is u itself: k = 1.
struct Coverage {
  double level;
  double k;
};
constexpr Coverage kNormalCoverage[] = {{0.6827, 1.0}, {0.90, 1.645}, {0.95, 1.960},
                                        {0.9545, 2.0}, {0.99, 2.576}, {0.9973, 3.0}};

double CoverageFactor(const ConfigNode& level) {
  const std::string hint =
      "Write level: sigma (the columns hold standard deviations) or the level of confidence "
      "of an expanded uncertainty, one of GUM Table G.1's: 0.6827, 0.90, 0.95, 0.9545, 0.99, "
      "0.9973 (U(95): level: 0.95)";
  if (level.IsScalar() && level.AsString() == "sigma") return 1.0;
  double p = 0.0;
  try {
    p = level.AsDouble();
  } catch (const InputError&) {
    throw level.Error("unknown uncertainty level '" + level.AsString() + "'", hint);
  }
  for (const Coverage& c : kNormalCoverage) {
    if (std::abs(p - c.level) < 1e-9) return c.k;
  }
  throw level.Error("no coverage factor for the level " + level.AsString(), hint);
}

// position_uncertainty: {columns: [ux, uy, uz], level: 0.95 | sigma, minimum: 0.0005}: each
// row's uncertainty of the position along the camera's axes, in the entry's length unit; cells
// below `minimum` (an instrument's rounded 0) read as it.
PositionUncertaintySpec ReadPositionUncertainty(const ConfigNode& node) {
  node.ExpectMap();
  node.ExpectKeys({"columns", "level", "minimum"});
  PositionUncertaintySpec spec;
  spec.where = node.location();
  spec.columns = Columns(Required(node, "columns",
                                  "List the x, y, z uncertainty columns: "
                                  "columns: [ux, uy, uz]"),
                         {"ux", "uy", "uz"});
  spec.coverage_factor =
      CoverageFactor(Required(node, "level",
                              "Say what the columns hold: level: sigma (standard deviations) "
                              "or level: 0.95 (expanded uncertainties at 95 %, U(95))"));
  if (node.Has("minimum")) {
    spec.minimum = node.GetDoubleIn(
        "minimum", 0.0, 1e-12, 1e6,
        "The smallest uncertainty a cell stands for, in the entry's length unit and at the "
        "columns' level: half the last digit the instrument writes (0.0005 for 0.001 mm)");
  }
  return spec;
}

// rotation_sigma: the instrument's stated orientation sigma about the camera's x, y, z (one
// number for all three), in the entry's angle unit.
std::array<double, 3> RotationSigmaRad(const ConfigNode& node, double to_rad) {
  std::array<double, 3> sigma;
  if (node.IsSequence()) {
    const std::vector<double> values = node.AsPositiveDoubles(3);
    for (int i = 0; i < 3; ++i) sigma[i] = values[i] * to_rad;
    return sigma;
  }
  const double value = node.AsDouble();
  if (!(value > 0.0)) {
    throw node.Error("a rotation sigma must be positive",
                     "A sigma of 0 says 'known perfectly': give the instrument's stated "
                     "orientation uncertainty (1 sigma, in the entry's angle unit)");
  }
  sigma.fill(value * to_rad);
  return sigma;
}

}  // namespace

void ReadUncertainties(const ConfigNode& node, ObservationSpec* spec) {
  if (node.Has("position_uncertainty")) {
    if (spec->camera_in_target) {
      throw node["position_uncertainty"].Error(
          "position_uncertainty is of the position as the table writes it, not the target's",
          "With pose_of: camera_in_target the table's position is the camera's; leave the "
          "uncertainty out");
    }
    spec->position_uncertainty = ReadPositionUncertainty(node["position_uncertainty"]);
  }
  if (node.Has("rotation_sigma")) {
    if (!spec->rotation && spec->transform.empty()) {
      throw node["rotation_sigma"].Error("rotation_sigma without a rotation",
                                         "Give rotation: too, or remove rotation_sigma");
    }
    spec->rotation_sigma_rad = RotationSigmaRad(node["rotation_sigma"], spec->to_rad);
  }
}

}  // namespace cellmetry::import_keys
