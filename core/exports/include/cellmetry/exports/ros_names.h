// The names cellmetry's frames get in ROS files (URDF links, tf frames), the same in every export
// so that a URDF and a tf launch file of one result fit together:
//
//   world                 world
//   <robot>.base          <robot>_base
//   <robot>.flange        <robot>_flange
//   joint i's frame       <robot>_link<i>        (URDF only; the joint is <robot>_joint<i>)
//   a tool (target)       its name               ("tool")
//   a camera              its name               ("cam1")
//
// Characters other than letters, digits, '_' and '/' become '_' (tf frame ids are written so).
#pragma once

#include <string>

namespace cellmetry {

std::string RosFrameName(const std::string& cellmetry_frame);

}  // namespace cellmetry
