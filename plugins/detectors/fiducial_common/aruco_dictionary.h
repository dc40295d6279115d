// ArUco dictionaries by name: OpenCV 4.6's predefined dictionaries (cv::aruco::
// PREDEFINED_DICTIONARY_NAME, opencv2/aruco/dictionary.hpp) or a custom one from a file as
// cv::aruco::Dictionary::readDictionary reads it (nmarkers, markersize, marker_<i>: bit strings;
// e.g. the OpenCV tutorial's tutorial_dict.yml).
#pragma once

#include <opencv2/aruco.hpp>

#include <string>
#include <vector>

#include "cellmetry/formats/config_node.h"

namespace cellmetry::fiducial {

// "DICT_4X4_50", ..., "DICT_ARUCO_ORIGINAL", "DICT_APRILTAG_36h11", in OpenCV's order.
const std::vector<std::string>& DictionaryNames();

// The dictionary named by the string at `node`; InputError at `node` listing the names when it is
// not one of them.
cv::Ptr<cv::aruco::Dictionary> PredefinedDictionary(const ConfigNode& node);

// The dictionary in the file named at `node` (relative to the config's folder); InputError when
// the file is missing or is not a dictionary.
cv::Ptr<cv::aruco::Dictionary> DictionaryFromFile(const ConfigNode& node);

}  // namespace cellmetry::fiducial
