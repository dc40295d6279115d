// `cellmetry calibrate-camera BOARD.yaml IMAGE... -o camera.yaml`: a camera's intrinsics from
// views of a flat board (camera_calibration.h), written as a camera file the detect jobs read.
// The file is written as an export is (export_file.h): where nothing is, or over an earlier one
// (kept as .previous); a user's own camera file only with --overwrite.
#include <cstdio>
#include <fstream>
#include <string>

#include "cellmetry/exports/export_file.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/imaging/camera_calibration.h"
#include "cellmetry/registry/registry.h"
#include "commands.h"

namespace cellmetry::app {
namespace {

// A camera file whose first line says calibrate-camera wrote it, from before its files carried
// the export marker: cellmetry's own, replaced as an export is.
bool WrittenByCalibrateCamera(const std::string& path) {
  std::ifstream in(path);
  std::string first;
  return std::getline(in, first) && first.rfind("# cellmetry calibrate-camera:", 0) == 0;
}

}  // namespace

void AddCalibrateCameraCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "calibrate-camera",
      "fit a camera's intrinsics and distortion to images of a flat board; write its camera file");
  static std::string board_path, output_path;
  static std::vector<std::string> image_paths;
  static CameraCalibrationOptions options;
  static bool overwrite = false;
  cmd->add_option("board", board_path,
                  "YAML with the board's detector, e.g. detector: {type: checkerboard, "
                  "corners_x: 9, corners_y: 6, square_mm: 25}")
      ->required();
  cmd->add_option("images", image_paths, "the board's images (3 or more views)")->required();
  cmd->add_option("-o,--output", output_path, "camera file to write (YAML)")->required();
  cmd->add_option("--min-keypoints", options.min_keypoints,
                  "a view with fewer keypoints is left out")
      ->check(CLI::Range(4, 1000000));
  cmd->add_flag("--fix-aspect-ratio", options.fix_aspect_ratio, "hold fx / fy at 1");
  cmd->add_flag("--zero-tangential", options.zero_tangential, "hold p1 = p2 = 0");
  cmd->add_flag("--fix-k3", options.fix_k3, "hold k3 = 0 (few views, or a narrow lens)");
  cmd->add_flag("--overwrite", overwrite,
                "replace a camera file cellmetry did not write (kept as <file>.previous)");
  cmd->callback([&context] {
    LoadPlugins(context);
    const ConfigNode root = ConfigNode::LoadFile(board_path);
    root.ExpectKeys({"detector"});
    const ConfigNode detector_config = root["detector"];
    detector_config.ExpectMap();
    options.detector_at = detector_config.location();
    auto detector =
        Registry::Global().CreateDetector(detector_config["type"].AsString(), detector_config);
    const bool replace = overwrite || WrittenByCalibrateCamera(output_path);
    CheckExportTarget(output_path, replace);  // before the work
    if (StopAfterCheck(output_path)) return;  // the images are read by the calibration
    const CameraCalibration c = CalibrateCamera(*detector, image_paths, options);
    WriteExportFile(output_path,
                    std::string("# ") + kExportMarker + ": camera file\n" + CameraFileText(c),
                    replace);
    std::printf("Camera calibration from %zu of %zu images: reprojection RMS %.3f px\n",
                c.views.size(), image_paths.size(), c.rms_px);
    const std::array<double, 9> values = IntrinsicValues(c.camera);
    for (int i = 0; i < 9; ++i) {
      std::printf("  %-3s %12.6g  sigma %.3g%s\n", IntrinsicNames()[i], values[i], c.sigma[i],
                  i < 4 ? " px" : "");
    }
    for (const CalibrationView& v : c.views) {
      std::printf("  %s: %d keypoints, %.3f px RMS\n", v.path.c_str(), v.keypoints, v.rms_px);
    }
    for (const auto& [path, why] : c.skipped) {
      std::printf("  %s: left out, %s\n", path.c_str(), why.c_str());
    }
    std::printf("  written: %s\n", output_path.c_str());
  });
}

}  // namespace cellmetry::app
