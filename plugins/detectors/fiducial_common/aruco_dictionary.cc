// ArUco dictionaries by name (aruco_dictionary.h): OpenCV 4.6's predefined ones, or a custom one
// read from a file.
#include "fiducial_common/aruco_dictionary.h"

#include <filesystem>
#include <utility>

#include "cellmetry/basics/text.h"

namespace cellmetry::fiducial {
namespace {

using cv::aruco::PREDEFINED_DICTIONARY_NAME;

const std::vector<std::pair<std::string, PREDEFINED_DICTIONARY_NAME>>& Table() {
  static const std::vector<std::pair<std::string, PREDEFINED_DICTIONARY_NAME>> table = {
      {"DICT_4X4_50", cv::aruco::DICT_4X4_50},
      {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
      {"DICT_4X4_250", cv::aruco::DICT_4X4_250},
      {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
      {"DICT_5X5_50", cv::aruco::DICT_5X5_50},
      {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
      {"DICT_5X5_250", cv::aruco::DICT_5X5_250},
      {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
      {"DICT_6X6_50", cv::aruco::DICT_6X6_50},
      {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
      {"DICT_6X6_250", cv::aruco::DICT_6X6_250},
      {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
      {"DICT_7X7_50", cv::aruco::DICT_7X7_50},
      {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
      {"DICT_7X7_250", cv::aruco::DICT_7X7_250},
      {"DICT_7X7_1000", cv::aruco::DICT_7X7_1000},
      {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL},
      {"DICT_APRILTAG_16h5", cv::aruco::DICT_APRILTAG_16h5},
      {"DICT_APRILTAG_25h9", cv::aruco::DICT_APRILTAG_25h9},
      {"DICT_APRILTAG_36h10", cv::aruco::DICT_APRILTAG_36h10},
      {"DICT_APRILTAG_36h11", cv::aruco::DICT_APRILTAG_36h11},
  };
  return table;
}

}  // namespace

const std::vector<std::string>& DictionaryNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& entry : Table()) out.push_back(entry.first);
    return out;
  }();
  return names;
}

cv::Ptr<cv::aruco::Dictionary> PredefinedDictionary(const ConfigNode& node) {
  const std::string name = node.AsString();
  for (const auto& [known, id] : Table()) {
    if (known == name) return cv::aruco::getPredefinedDictionary(id);
  }
  const std::string nearest = NearestWord(name, DictionaryNames());
  throw node.Error("unknown ArUco dictionary '" + name + "'",
                   (nearest.empty() ? "" : "Did you mean '" + nearest + "'? ") +
                       "Known dictionaries: " + Join(DictionaryNames()) +
                       "; or give dictionary_file: with a custom one");
}

cv::Ptr<cv::aruco::Dictionary> DictionaryFromFile(const ConfigNode& node) {
  const std::string path = node.ResolvePath(node.AsString());
  if (!std::filesystem::is_regular_file(path)) {
    throw node.Error("dictionary file '" + path + "' does not exist");
  }
  auto dictionary = cv::makePtr<cv::aruco::Dictionary>();
  bool read = false;
  try {
    cv::FileStorage storage(path, cv::FileStorage::READ);
    read = storage.isOpened() && dictionary->readDictionary(storage.root());
  } catch (const cv::Exception& e) {
    throw node.Error("dictionary file '" + path + "' cannot be read: " + e.msg);
  }
  if (!read || dictionary->bytesList.empty() || dictionary->markerSize < 2) {
    throw node.Error("'" + path + "' is not an ArUco dictionary",
                     "Write it with cv::aruco::Dictionary::writeDictionary (keys nmarkers, "
                     "markersize, marker_0, ...)");
  }
  return dictionary;
}

}  // namespace cellmetry::fiducial
