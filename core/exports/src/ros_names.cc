// cellmetry frame names as ROS frame names (ros_names.h).
#include "cellmetry/exports/ros_names.h"

#include <cctype>

namespace cellmetry {

std::string RosFrameName(const std::string& frame) {
  std::string name = frame;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '/') c = '_';
  }
  return name;
}

}  // namespace cellmetry
