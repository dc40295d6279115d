// Small pieces of XML text for the exports that write XML (URDF, ROS launch files).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/xml_escape.h"  // EscapeXml: text and attribute values

namespace cellmetry {

// One <!-- ... --> comment of `lines`, each indented by `indent`; "--", which XML forbids in a
// comment, becomes "- -".
std::string XmlComment(const std::vector<std::string>& lines, const std::string& indent);

// `<origin xyz="..." rpy="..."/>` of a pose given in mm, written in metres (URDF's unit) with
// every digit a double has (ExactNumber), rotation as fixed-axis roll, pitch, yaw.
std::string UrdfOrigin(const Pose& T_parent_child_mm);

}  // namespace cellmetry
