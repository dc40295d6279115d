// Registers the `charuco` detector: a ChArUco board (OpenCV 4.6 contrib cv::aruco).
//
//   detector: {type: charuco, dictionary: DICT_6X6_250, squares_x: 5, squares_y: 7,
//              square_mm: 40, marker_mm: 20}
#include <string>

#include "cellmetry/registry/registry.h"
#include "charuco_detector.h"
#include "fiducial_common/aruco_dictionary.h"

namespace cellmetry::charuco {
namespace {

int Squares(const ConfigNode& config, const std::string& key) {
  if (!config.Has(key)) {
    throw config.Error("missing key '" + key + "'",
                       "Give the board's squares per row (squares_x) and per column (squares_y)");
  }
  const int squares = config[key].AsInt();
  if (squares < 2) {
    throw config[key].Error("must be at least 2", "Squares, not inner corners, e.g. 5 x 7");
  }
  return squares;
}

double Length(const ConfigNode& config, const std::string& key, const std::string& what) {
  if (!config.Has(key)) throw config.Error("missing key '" + key + "'", "Give " + what + " in mm");
  const double mm = config[key].AsDouble();
  if (!(mm > 0)) throw config[key].Error("must be positive", "Give " + what + " in mm");
  return mm;
}

void ReadBoard(const ConfigNode& config, CharucoTarget* t) {
  t->squares_x = Squares(config, "squares_x");
  t->squares_y = Squares(config, "squares_y");
  t->square_mm = Length(config, "square_mm", "the side of a chessboard square");
  t->marker_mm = Length(config, "marker_mm", "the side of a marker's black square");
  if (t->marker_mm >= t->square_mm) {
    throw config["marker_mm"].Error(
        "a marker must be smaller than its square (square_mm " + std::to_string(t->square_mm) + ")",
        "Markers sit inside the white squares with white paper around them: usually "
        "marker_mm is 0.5-0.8 of square_mm");
  }
  const int size = t->dictionary->bytesList.rows;
  if (t->markers() > size) {
    throw config.Error("a " + std::to_string(t->squares_x) + " x " + std::to_string(t->squares_y) +
                           " board needs marker ids 0.." + std::to_string(t->markers() - 1) +
                           " but the dictionary has ids 0.." + std::to_string(size - 1),
                       "Use a smaller board or a larger dictionary");
  }
}

std::unique_ptr<Detector> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "dictionary", "dictionary_file", "squares_x", "squares_y", "square_mm",
                     "marker_mm", "refine_markers", "min_markers", "subpix", "subpix_window_px",
                     "subpix_max_iterations", "subpix_accuracy_px", "sigma_px"});
  CharucoOptions o;
  if (config.Has("dictionary") == config.Has("dictionary_file")) {
    throw config.Error("give exactly one of dictionary and dictionary_file",
                       "e.g. dictionary: DICT_6X6_250");
  }
  if (config.Has("dictionary")) {
    o.target.dictionary = fiducial::PredefinedDictionary(config["dictionary"]);
    o.dictionary_name = config["dictionary"].AsString();
  } else {
    o.target.dictionary = fiducial::DictionaryFromFile(config["dictionary_file"]);
    o.dictionary_name = "custom-dictionary";
  }
  ReadBoard(config, &o.target);
  o.refine_markers = config.GetBool("refine_markers", o.refine_markers);
  o.min_markers = config.GetInt("min_markers", o.min_markers);
  if (o.min_markers < 1 || o.min_markers > 2) {
    throw config["min_markers"].Error("must be 1 or 2",
                                      "A chessboard corner has at most 2 neighbouring markers");
  }
  o.subpix = config.GetBool("subpix", o.subpix);
  o.subpix_window_px = config.GetInt("subpix_window_px", o.subpix_window_px);
  if (o.subpix_window_px < 2) {
    throw config["subpix_window_px"].Error("must be at least 2",
                                           "The half-width in pixels, e.g. 5");
  }
  o.subpix_max_iterations = config.GetInt("subpix_max_iterations", o.subpix_max_iterations);
  if (o.subpix_max_iterations < 1) {
    throw config["subpix_max_iterations"].Error("must be at least 1");
  }
  o.subpix_accuracy_px = config.GetDouble("subpix_accuracy_px", o.subpix_accuracy_px);
  if (!(o.subpix_accuracy_px > 0)) {
    throw config["subpix_accuracy_px"].Error("must be positive",
                                             "The corner step that ends refinement, e.g. 0.01");
  }
  o.sigma_px = config.GetDouble("sigma_px", o.sigma_px);
  if (!(o.sigma_px > 0)) {
    throw config["sigma_px"].Error("must be positive", "A corner's standard deviation in pixels");
  }
  return std::make_unique<CharucoDetector>(std::move(o));
}

}  // namespace
}  // namespace cellmetry::charuco

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.kind = cellmetry::PluginKind::kDetector;
  info.name = "charuco";
  info.description =
      "a ChArUco board (OpenCV 4.6 contrib cv::aruco::CharucoBoard), found in part when partly "
      "hidden; keypoint id = its chessboard corner's index in OpenCV's board";
  info.options = {
      {"dictionary", "", "",
       "the markers' predefined dictionary: DICT_4X4_50 ... DICT_7X7_1000, "
       "DICT_ARUCO_ORIGINAL, DICT_APRILTAG_16h5/25h9/36h10/36h11"},
      {"dictionary_file", "", "",
       "instead of dictionary: a custom one as cv::aruco::Dictionary::writeDictionary writes it"},
      {"squares_x", "", "",
       "chessboard squares per row (CharucoBoard::create's squaresX); the target frame is "
       "OpenCV's: origin at the board's top-left corner, x along a row, y down, z into the paper"},
      {"squares_y", "", "", "chessboard squares per column; the top-left square is black"},
      {"square_mm", "mm", "", "side of a chessboard square"},
      {"marker_mm", "mm", "",
       "side of a marker's black square (less than square_mm); markers have ids 0, 1, ... in "
       "the white squares, row by row"},
      {"refine_markers", "", "true",
       "refineDetectedMarkers: look again for the board's missed markers where the found ones "
       "say they are"},
      {"min_markers", "", "2",
       "1 or 2: found neighbouring markers a chessboard corner needs to be reported "
       "(interpolateCornersCharuco's minMarkers; 1 also gives corners on the board's edge with "
       "one marker seen)"},
      {"subpix", "", "true",
       "run cornerSubPix on after OpenCV's (which stops at 0.1 px steps), in a window clear of "
       "the neighbouring markers"},
      {"subpix_window_px", "px", "5", "that cornerSubPix's window half-width at most"},
      {"subpix_max_iterations", "", "50", "that cornerSubPix's iterations at most"},
      {"subpix_accuracy_px", "px", "0.01", "that cornerSubPix stops when a step is below this"},
      {"sigma_px", "px", "0.1",
       "corner standard deviation per image axis, covariance sigma^2 I (allows for real blur, "
       "print and focus beyond the rendered views' noise)"},
  };
  registry->AddDetector(info, &cellmetry::charuco::Create);
}
