// The opening comment of every export (export_header.h).
#include "cellmetry/exports/export_header.h"

#include <cstdio>

#include "cellmetry/exports/export_file.h"

namespace cellmetry {

std::vector<std::string> ExportHeader(const CalibratedCell& cell, const std::string& format,
                                      const CalibratedRobot* robot, const std::string& command) {
  std::vector<std::string> lines = {std::string(kExportMarker) + ": " + format + " of " +
                                    cell.json_path};
  if (robot) {
    lines.push_back("robot '" + robot->name + "': model " + robot->model_type + ", config " +
                    robot->model_file + " at the values the result fitted");
  }
  lines.push_back("A later `" + command +
                  "` to this path replaces this file and keeps it as "
                  "<file>.previous.");
  return lines;
}

std::string ValueWithSigma(const FittedScalar& s) {
  char text[96];
  if (s.sigma) {
    std::snprintf(text, sizeof text, "%.9g +- %.2g %s", s.value, *s.sigma, s.unit.c_str());
  } else {
    std::snprintf(text, sizeof text, "%.9g %s (held: not identifiable)", s.value, s.unit.c_str());
  }
  return text;
}

std::string FrameSigmaText(const CalibratedFrame& frame) {
  auto part = [&frame](int offset) {
    std::string text = "(";
    for (int i = 0; i < 3; ++i) {
      char value[32] = "held";
      if (frame.sigma[offset + i])
        std::snprintf(value, sizeof value, "%.2g", *frame.sigma[offset + i]);
      text += (i ? ", " : "") + std::string(value);
    }
    return text + ")";
  };
  return frame.name + " in " + frame.parent + ": sigma xyz " + part(0) + " mm, rot " + part(3) +
         " rad";
}

std::vector<std::string> LeftOut(const CalibratedCell& cell, const CalibratedRobot& robot,
                                 const std::vector<std::string>& chain_gaps) {
  std::vector<std::string> lines = chain_gaps;
  for (const auto& e : robot.effects) {
    lines.push_back("effect " + e.name + " = " + ValueWithSigma(e) +
                    " (not rigid geometry: no place for it here)");
  }
  for (const auto& e : cell.camera_effects) {
    lines.push_back("measurement effect " + e.name + " = " + ValueWithSigma(e) +
                    " (acts on the cameras' measurements, not on the robot)");
  }
  return lines;
}

std::string CommentLines(const std::vector<std::string>& lines, const std::string& prefix) {
  std::string text;
  for (const auto& line : lines) text += prefix + line + "\n";
  return text;
}

}  // namespace cellmetry
