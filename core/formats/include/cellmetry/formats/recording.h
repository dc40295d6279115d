// Recording: the `cellmetry-recording/1` folder format (docs/formats.md).
//
//   recording.yaml    units, robots (name -> joint count), cameras (a name, or
//                     {name, on: <robot>} for one riding on that robot's flange: eye in hand),
//                     targets (name -> carrier)
//   samples.csv       sample,robot,pose,q1..qN[,t][,temperature][,payload]
//   observations.csv  sample,camera,target,x,y,z[,rx,ry,rz]   (target pose in the camera frame)
//                     [,cov_xx..cov_zz][,rcov_xx..rcov_zz]    (position / rotation covariance)
//   images.csv        optional: sample,camera,view,path
//   truth.yaml        only in simulations; never read by a calibration
//
// Inside cellmetry every length is mm and every angle rad; a recording in m or deg is converted
// on reading and written back in mm/rad. ReadRecording checks every cross reference (an
// observation naming an unknown sample, camera or target; a sample with the wrong joint count)
// and raises InputError with the file and line.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cellmetry {

inline constexpr char kRecordingFormat[] = "cellmetry-recording/1";
inline constexpr char kWorldCarrier[] = "world";

struct Sample {
  int id = 0;
  std::string robot;
  int pose = 0;           // captures of one commanded pose share it (repeatability)
  std::vector<double> q;  // joint readings, rad (delta: the three motor angles)
  std::optional<double> time_s;
  std::optional<double> temperature_c;
  std::optional<double> payload_kg;
  int line = 0;  // line in samples.csv, for messages (0: not read from a file)
};

struct Observation {
  int sample = 0;
  std::string camera;
  std::string target;
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();  // target origin in the camera frame
  std::optional<Eigen::Vector3d> rvec;                    // target rotation in the camera frame
  std::optional<Eigen::Matrix3d> covariance_mm2;          // of position_mm, when measured
  std::optional<Eigen::Matrix3d>
      rotation_covariance_rad2;  // of the rotation, about the camera axes
  int line = 0;                  // line in observations.csv, for messages
};

struct ImageRef {
  int sample = 0;
  std::string camera;
  std::string view;  // left | right | mono
  std::string path;  // relative to the recording folder
};

struct Recording {
  std::string folder;  // where it was read from (empty for one built in memory)
  std::string description;
  std::map<std::string, int> robots;  // robot name -> joint count
  std::vector<std::string> cameras;
  // A camera riding on a robot's flange (eye in hand) -> that robot; the others stand still.
  std::map<std::string, std::string> camera_mounts;
  std::map<std::string, std::string> targets;  // target name -> robot name or "world"
  std::vector<Sample> samples;                 // in capture order
  std::vector<Observation> observations;
  std::vector<ImageRef> images;

  // Index into `samples` of the sample with this id; -1 if absent.
  int SampleIndex(int id) const;
  bool HasCamera(const std::string& name) const;
  // Whether `target` is one some robot carries (not the world's, nor one the recording lacks).
  bool IsCarried(const std::string& target) const;
};

// Reads and validates a recording folder. Raises InputError on any defect.
Recording ReadRecording(const std::string& folder);

// observations.csv text (mm, rad; covariance columns when any observation has one).
std::string ObservationsCsv(const std::vector<Observation>& observations);

// Writes a recording folder atomically (mm, rad). `truth_yaml`, when not empty, goes to truth.yaml.
// `write_extra`, when given, writes more files (images) into the staging folder before the
// folder is committed.
void WriteRecording(const Recording& recording, const std::string& folder,
                    const std::string& truth_yaml = "",
                    const std::function<void(const std::string&)>& write_extra = {});

}  // namespace cellmetry
