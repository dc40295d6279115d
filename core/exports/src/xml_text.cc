// XML text pieces (xml_text.h).
#include "cellmetry/exports/xml_text.h"

#include "cellmetry/exports/roll_pitch_yaw.h"
#include "cellmetry/formats/exact_number.h"

namespace cellmetry {

std::string XmlComment(const std::vector<std::string>& lines, const std::string& indent) {
  std::string body;
  for (size_t i = 0; i < lines.size(); ++i) {
    std::string line = lines[i];
    for (size_t at = line.find("--"); at != std::string::npos; at = line.find("--", at)) {
      line.replace(at, 2, "- -");
    }
    body += (i == 0 ? indent + "<!-- " : indent + "     ") + line + "\n";
  }
  if (body.empty()) return "";
  body.back() = ' ';
  return body + "-->\n";
}

std::string UrdfOrigin(const Pose& T) {
  const RollPitchYawAngles a = RollPitchYaw(T.R);
  const Eigen::Vector3d m = T.t / 1000.0;
  return "<origin xyz=\"" + ExactNumber(m.x()) + " " + ExactNumber(m.y()) + " " +
         ExactNumber(m.z()) + "\" rpy=\"" + ExactNumber(a.roll) + " " + ExactNumber(a.pitch) + " " +
         ExactNumber(a.yaw) + "\"/>";
}

}  // namespace cellmetry
