// Registers the `checkerboard` detector: a plain chessboard, corners by findChessboardCornersSB.
//
//   detector: {type: checkerboard, corners_x: 9, corners_y: 6, square_mm: 25}
#include <string>

#include "cellmetry/registry/registry.h"
#include "checkerboard_detector.h"

namespace cellmetry::checkerboard {
namespace {

// An inner-corner count: at least 3 (findChessboardCornersSB's smallest pattern).
int Corners(const ConfigNode& config, const std::string& key) {
  if (!config.Has(key)) {
    throw config.Error("missing key '" + key + "'",
                       "Give the board's inner corners per row (corners_x) and per column "
                       "(corners_y): a board of 10 x 7 squares has 9 x 6 inner corners");
  }
  const int corners = config[key].AsInt();
  if (corners < 3) {
    throw config[key].Error("must be at least 3",
                            "Inner corners, where four squares meet: squares per side minus 1");
  }
  return corners;
}

std::unique_ptr<Detector> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "corners_x", "corners_y", "square_mm", "normalize_image", "exhaustive",
                     "accuracy", "sigma_px"});
  CheckerboardOptions o;
  o.target.corners_x = Corners(config, "corners_x");
  o.target.corners_y = Corners(config, "corners_y");
  if ((o.target.corners_x + o.target.corners_y) % 2 == 0) {
    throw config.Error(
        "a " + std::to_string(o.target.corners_x) + " x " + std::to_string(o.target.corners_y) +
            " inner-corner board looks the same turned by 180 degrees: its corner order, and "
            "the pose, would flip between images",
        "Use a board with one even and one odd count of inner corners, e.g. 9 x 6 (10 x 7 "
        "squares)");
  }
  if (!config.Has("square_mm")) {
    throw config.Error("missing key 'square_mm'", "Give the side of a square in mm");
  }
  o.target.square_mm = config["square_mm"].AsDouble();
  if (!(o.target.square_mm > 0)) {
    throw config["square_mm"].Error("must be positive", "The side of a square in mm, e.g. 25");
  }
  o.normalize_image = config.GetBool("normalize_image", o.normalize_image);
  o.exhaustive = config.GetBool("exhaustive", o.exhaustive);
  o.accuracy = config.GetBool("accuracy", o.accuracy);
  o.sigma_px = config.GetDouble("sigma_px", o.sigma_px);
  if (!(o.sigma_px > 0)) {
    throw config["sigma_px"].Error("must be positive", "A corner's standard deviation in pixels");
  }
  return std::make_unique<CheckerboardDetector>(std::move(o));
}

}  // namespace
}  // namespace cellmetry::checkerboard

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.kind = cellmetry::PluginKind::kDetector;
  info.name = "checkerboard";
  info.description =
      "a plain checkerboard (OpenCV's findChessboardCornersSB), the whole board in view; "
      "keypoint id = row * corners_x + col of its inner corners";
  info.options = {
      {"corners_x", "", "",
       "inner corners per row (squares per row minus 1); the target's x runs along a row from "
       "the top-left inner corner, y down the board, z into the paper"},
      {"corners_y", "", "",
       "inner corners per column; one of corners_x and corners_y even, the other odd (so the "
       "board's top-left square, black, tells its orientation)"},
      {"square_mm", "mm", "", "side of a square"},
      {"normalize_image", "", "false",
       "CALIB_CB_NORMALIZE_IMAGE: equalize the histogram before detection (for boards not found "
       "in dim or uneven light; equalizing bends the blurred edges: on rendered views the worst "
       "corner went from 0.08 to 0.42 px)"},
      {"exhaustive", "", "false",
       "CALIB_CB_EXHAUSTIVE: a slower, more thorough search (steep or blurred views)"},
      {"accuracy", "", "true",
       "CALIB_CB_ACCURACY: locate the corners on an upsampled image (less aliasing, slower)"},
      {"sigma_px", "px", "0.1",
       "corner standard deviation per image axis, covariance sigma^2 I (allows for real blur, "
       "print and focus beyond the rendered views' noise)"},
  };
  registry->AddDetector(info, &cellmetry::checkerboard::Create);
}
