// Registers the `aruco` detector: OpenCV 4.6 contrib ArUco markers, single or on a grid board.
//
//   detector: {type: aruco, dictionary: DICT_6X6_250, marker_length_mm: 40,
//              markers_x: 5, markers_y: 7, separation_mm: 10, first_id: 0}   # a grid board
//   detector: {type: aruco, dictionary: DICT_4X4_50, marker_length_mm: 30,
//              marker_ids: [3, 7]}                                            # single markers
#include <set>
#include <string>

#include "cellmetry/registry/registry.h"
#include "aruco_detector.h"
#include "fiducial_common/aruco_dictionary.h"

namespace cellmetry::aruco {
namespace {

double Positive(const ConfigNode& config, const std::string& key, double fallback,
                const std::string& hint) {
  const double value = config.GetDouble(key, fallback);
  if (!(value > 0.0)) throw config[key].Error("must be positive", hint);
  return value;
}

int RefinementMethod(const ConfigNode& node) {
  const std::string name = node.AsString();
  if (name == "none") return cv::aruco::CORNER_REFINE_NONE;
  if (name == "subpix") return cv::aruco::CORNER_REFINE_SUBPIX;
  if (name == "contour") return cv::aruco::CORNER_REFINE_CONTOUR;
  if (name == "apriltag") return cv::aruco::CORNER_REFINE_APRILTAG;
  throw node.Error("unknown corner refinement '" + name + "'",
                   "Use one of none, subpix, contour, apriltag");
}

// detectMarkers' parameters and the plugin's own refinement stages (aruco_detector.h). The
// sub-pixel stage is the plugin's (a window fitted to each marker), so OpenCV is asked for none.
void ReadRefinement(const ConfigNode& config, ArucoOptions* o) {
  o->parameters = cv::aruco::DetectorParameters::create();
  const int method = config.Has("corner_refinement") ? RefinementMethod(config["corner_refinement"])
                                                     : cv::aruco::CORNER_REFINE_SUBPIX;
  o->subpix = method == cv::aruco::CORNER_REFINE_SUBPIX;
  o->parameters->cornerRefinementMethod = o->subpix ? cv::aruco::CORNER_REFINE_NONE : method;
  o->subpix_window_px = config.GetInt("subpix_window_px", o->subpix_window_px);
  if (o->subpix_window_px < 2) {
    throw config["subpix_window_px"].Error("must be at least 2",
                                           "The half-width in pixels, e.g. 5");
  }
  o->subpix_max_iterations = config.GetInt("subpix_max_iterations", o->subpix_max_iterations);
  if (o->subpix_max_iterations < 1)
    throw config["subpix_max_iterations"].Error("must be at least 1");
  o->subpix_accuracy_px = Positive(config, "subpix_accuracy_px", o->subpix_accuracy_px,
                                   "The corner step that ends refinement, e.g. 0.01");
  o->edge_refinement = config.GetBool("edge_refinement", o->edge_refinement);
}

void ReadBoard(const ConfigNode& config, ArucoTarget* t) {
  for (const char* key : {"markers_x", "markers_y", "separation_mm"}) {
    if (!config.Has(key)) {
      throw config.Error(std::string("a grid board needs ") + key,
                         "Give markers_x, markers_y and separation_mm (and first_id)");
    }
  }
  if (config.Has("marker_ids")) {
    throw config["marker_ids"].Error("marker_ids is for single markers, not a grid board",
                                     "A board's ids are first_id, first_id + 1, ...");
  }
  t->markers_x = config["markers_x"].AsInt();
  t->markers_y = config["markers_y"].AsInt();
  if (t->markers_x < 1) throw config["markers_x"].Error("must be at least 1");
  if (t->markers_y < 1) throw config["markers_y"].Error("must be at least 1");
  t->separation_mm = config["separation_mm"].AsDouble();
  if (t->separation_mm < 0) throw config["separation_mm"].Error("must not be negative");
  t->first_id = config.GetInt("first_id", 0);
  const int size = t->dictionary->bytesList.rows;
  if (t->first_id < 0 || t->first_id + t->markers_x * t->markers_y > size) {
    throw config.Error("the board needs marker ids " + std::to_string(t->first_id) + ".." +
                           std::to_string(t->first_id + t->markers_x * t->markers_y - 1) +
                           " but the dictionary has ids 0.." + std::to_string(size - 1),
                       "Use a smaller board, a lower first_id or a larger dictionary");
  }
}

void ReadSingle(const ConfigNode& config, ArucoTarget* t) {
  for (const char* key : {"first_id", "separation_mm"}) {
    if (config.Has(key)) {
      throw config[key].Error(std::string(key) + " is for grid boards",
                              "Give markers_x and markers_y too, or list marker_ids");
    }
  }
  const int size = t->dictionary->bytesList.rows;
  if (!config.Has("marker_ids")) {
    for (int id = 0; id < size; ++id) t->single_ids.push_back(id);
    return;
  }
  const ConfigNode list = config["marker_ids"];
  list.ExpectSequence();
  std::set<int> seen;
  for (const ConfigNode& element : list.Elements()) {
    const int id = element.AsInt();
    if (id < 0 || id >= size) {
      throw element.Error("marker id " + std::to_string(id) + " is not in the dictionary",
                          "Ids run from 0 to " + std::to_string(size - 1));
    }
    if (!seen.insert(id).second)
      throw element.Error("marker id " + std::to_string(id) + " is listed twice");
    t->single_ids.push_back(id);
  }
  if (t->single_ids.empty())
    throw list.Error("lists no marker", "List at least one id, or leave marker_ids out for all");
}

std::unique_ptr<Detector> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "dictionary", "dictionary_file", "marker_length_mm", "marker_ids",
                     "markers_x", "markers_y", "separation_mm", "first_id", "corner_refinement",
                     "subpix_window_px", "subpix_max_iterations", "subpix_accuracy_px",
                     "edge_refinement", "sigma_px"});
  ArucoOptions options;
  if (config.Has("dictionary") == config.Has("dictionary_file")) {
    throw config.Error("give exactly one of dictionary and dictionary_file",
                       "e.g. dictionary: DICT_6X6_250");
  }
  if (config.Has("dictionary")) {
    options.target.dictionary = fiducial::PredefinedDictionary(config["dictionary"]);
    options.dictionary_name = config["dictionary"].AsString();
  } else {
    options.target.dictionary = fiducial::DictionaryFromFile(config["dictionary_file"]);
    options.dictionary_name = "custom-dictionary";
  }
  if (!config.Has("marker_length_mm")) {
    throw config.Error("missing key 'marker_length_mm'",
                       "Give the side of a marker's black square in mm");
  }
  options.target.marker_length_mm =
      Positive(config, "marker_length_mm", 0.0, "The side of the black square in mm");
  if (config.Has("markers_x") || config.Has("markers_y")) {
    ReadBoard(config, &options.target);
  } else {
    ReadSingle(config, &options.target);
  }
  ReadRefinement(config, &options);
  options.sigma_px =
      Positive(config, "sigma_px", options.sigma_px, "A corner's standard deviation in pixels");
  return std::make_unique<ArucoDetector>(std::move(options));
}

}  // namespace
}  // namespace cellmetry::aruco

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.kind = cellmetry::PluginKind::kDetector;
  info.name = "aruco";
  info.description =
      "ArUco markers (OpenCV 4.6 contrib cv::aruco), single or on a grid board; keypoint id = "
      "marker id * 4 + corner (top-left, top-right, bottom-right, bottom-left)";
  info.options = {
      {"dictionary", "", "",
       "a predefined dictionary: DICT_4X4_50 ... DICT_7X7_1000, "
       "DICT_ARUCO_ORIGINAL, DICT_APRILTAG_16h5/25h9/36h10/36h11"},
      {"dictionary_file", "", "",
       "instead of dictionary: a custom one as "
       "cv::aruco::Dictionary::writeDictionary writes it"},
      {"marker_length_mm", "mm", "", "side of a marker's black square"},
      {"marker_ids", "", "all",
       "single markers: the ids to report, each centred on the target "
       "origin (estimatePoseSingleMarkers' frame, z out of the paper)"},
      {"markers_x", "", "",
       "grid board: markers per row (cv::aruco::GridBoard; origin at the "
       "top-left marker's top-left corner, y down, z into the paper)"},
      {"markers_y", "", "", "grid board: markers per column"},
      {"separation_mm", "mm", "", "grid board: gap between neighbouring markers"},
      {"first_id", "", "0", "grid board: id of the top-left marker; row by row after it"},
      {"corner_refinement", "", "subpix",
       "none | subpix | contour | apriltag: OpenCV's CORNER_REFINE_* (subpix: the plugin's "
       "cornerSubPix per marker, where edge refinement cannot refine)"},
      {"subpix_window_px", "px", "5",
       "cornerSubPix window half-width at most (shrunk to stay inside a marker's border cell)"},
      {"subpix_max_iterations", "", "50", "cornerSubPix iterations at most"},
      {"subpix_accuracy_px", "px", "0.01", "cornerSubPix stops when a step is below this"},
      {"edge_refinement", "", "true",
       "fit each side as a line through sub-pixel edge points, corners where they meet "
       "(cornerSubPix is pulled ~0.2 px into blurred markers; markers too small for their blur "
       "keep detectMarkers' corners)"},
      {"sigma_px", "px", "0.1",
       "corner standard deviation per image axis, covariance sigma^2 I (rendered views with "
       "noise 2 gray levels measure 0.01-0.02 px; 0.1 allows for real blur, print and focus)"},
  };
  registry->AddDetector(info, &cellmetry::aruco::Create);
}
