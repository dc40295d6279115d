#include "cellmetry/experiments/marker_comparison.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <sstream>

#include "cellmetry/basics/progress.h"
#include "cellmetry/basics/statistics.h"
#include "cellmetry/formats/checkpoint.h"
#include "cellmetry/formats/config_fields.h"
#include "cellmetry/imaging/target_pose.h"

namespace cellmetry {
namespace {

// How a detector's target is shown: the spec's poses place a marker frame with its z out of the
// printed side of the first face and its origin at the centre of the layout, and that centre is
// the point measured. For the dot, the 13-dot pattern and an ArUco marker this is their own
// frame. An AprilTag board's frame has its origin at the top-left tag corner and z into the
// paper: shown as it is, the printed side faced away from the camera and nothing was detected.
struct Presentation {
  Eigen::Matrix3d R_target_marker = Eigen::Matrix3d::Identity();
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  // target frame
  std::vector<MarkerPoint> centred_layout;              // layout about the centre

  Presentation(const Detector& detector, const std::vector<MarkerFace>& faces) {
    if (!faces.empty()) R_target_marker = faces.front().T_target_face.R;
    const auto& layout = detector.layout();
    for (const auto& p : layout) centre_mm += p.p_target_mm;
    if (!layout.empty()) centre_mm /= static_cast<double>(layout.size());
    centred_layout = layout;
    for (auto& p : centred_layout) p.p_target_mm -= centre_mm;
  }
  // T_cam_target for a marker frame at T_cam_marker (whose origin is then the centre).
  Pose Shown(const Pose& T_cam_marker) const {
    Pose T;
    T.R = T_cam_marker.R * R_target_marker.transpose();
    T.t = T_cam_marker.t - T.R * centre_mm;
    return T;
  }
};

// The noise-free images of both stereo cameras of a marker at T_cam_marker (left camera frame).
// The static captures share one pair and draw only fresh sensor noise.
struct IdealPair {
  std::vector<float> left, right;
};

IdealPair RenderPair(const MarkerComparisonSpec& spec, const std::vector<MarkerFace>& faces,
                     const Presentation& shown, const Pose& T_cam_marker) {
  const Pose T_cam_target = shown.Shown(T_cam_marker);
  return {
      RenderIdeal(spec.rig.left, {{T_cam_target, &faces}}, spec.render),
      RenderIdeal(spec.rig.right, {{spec.rig.T_right_left * T_cam_target, &faces}}, spec.render)};
}

struct StereoShot {
  std::optional<TriangulatedPoint> origin;
  double ms = 0.0;  // left image's detection time
};

StereoShot Shoot(const MarkerComparisonSpec& spec, Detector& detector, const Presentation& shown,
                 const IdealPair& ideal, std::mt19937& rng) {
  const PinholeCamera& lc = spec.rig.left;
  const PinholeCamera& rc = spec.rig.right;
  const GrayImage left = SensorImage(ideal.left, lc.width, lc.height, spec.render, rng);
  const GrayImage right = SensorImage(ideal.right, rc.width, rc.height, spec.render, rng);
  StereoShot shot;
  const auto start = std::chrono::steady_clock::now();
  const Detection l = detector.Detect(left.view());
  shot.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const Detection r = detector.Detect(right.view());
  if (l.found() && r.found()) {
    shot.origin =
        TargetOriginFromStereo(spec.rig, l.keypoints, r.keypoints, shown.centred_layout, 0);
  }
  return shot;
}

// Cramer-Rao floor of the origin at the static pose (whose ideal pair is `ideal`): each view's
// image-position bound as keypoint covariance, triangulated.
Eigen::Vector3d Floor(const MarkerComparisonSpec& spec, const IdealPair& ideal) {
  const Eigen::Vector2d l_crb = ImageShiftCramerRao(ideal.left, spec.rig.left.width,
                                                    spec.rig.left.height, spec.render.noise_sigma);
  const Eigen::Vector2d r_crb = ImageShiftCramerRao(ideal.right, spec.rig.right.width,
                                                    spec.rig.right.height, spec.render.noise_sigma);
  Keypoint l, r;
  l.pixel = spec.rig.left.Project(spec.static_pose.t);
  r.pixel = spec.rig.right.Project(spec.rig.T_right_left * spec.static_pose.t);
  l.covariance_px2 = l_crb.cwiseAbs2().asDiagonal();
  r.covariance_px2 = r_crb.cwiseAbs2().asDiagonal();
  const auto point = Triangulate(spec.rig, l, r);
  return point ? Eigen::Vector3d(point->covariance_mm2.diagonal().cwiseSqrt())
               : Eigen::Vector3d::Zero();
}

Pose RandomWorkspacePose(const MarkerComparisonSpec& spec, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(spec.depth_mm.x(), spec.depth_mm.y());
  const Eigen::Vector3d tilt(spec.tilt_rad * u(rng), spec.tilt_rad * u(rng), M_PI * u(rng));
  // Facing the camera (z out of the paper toward it), then tilted.
  const Eigen::Matrix3d facing =
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return Pose{
      RotationFromRvec(tilt.data()) * facing,
      Eigen::Vector3d(spec.lateral_mm * u(rng), spec.lateral_mm * 0.6 * u(rng), depth(rng))};
}

MarkerRow CompareOne(const MarkerComparisonSpec& spec, const std::string& label,
                     Detector& detector) {
  MarkerRow row;
  row.label = label;
  const std::vector<MarkerFace> faces = detector.Faces(20.0);
  const Presentation shown(detector, faces);
  std::mt19937 rng(spec.seed);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> ms;
  const IdealPair static_pair = RenderPair(spec, faces, shown, spec.static_pose);
  for (int i = 0; i < spec.captures; ++i) {
    const StereoShot shot = Shoot(spec, detector, shown, static_pair, rng);
    ms.push_back(shot.ms);
    if (shot.origin) points.push_back(shot.origin->p_left_mm);
  }
  row.captures_found = static_cast<int>(points.size());
  if (points.size() >= 2) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : points) mean += p;
    mean /= points.size();
    Eigen::Vector3d var = Eigen::Vector3d::Zero();
    for (const auto& p : points) var += (p - mean).cwiseAbs2();
    row.repeatability_mm = (var / (points.size() - 1)).cwiseSqrt();
    row.static_bias_mm = (mean - spec.static_pose.t).norm();
  }
  row.floor_mm = Floor(spec, static_pair);
  double sum2 = 0.0;
  for (int i = 0; i < spec.positions; ++i) {
    const Pose pose = RandomWorkspacePose(spec, rng);
    const StereoShot shot = Shoot(spec, detector, shown, RenderPair(spec, faces, shown, pose), rng);
    ms.push_back(shot.ms);
    if (!shot.origin) continue;
    ++row.positions_found;
    sum2 += (shot.origin->p_left_mm - pose.t).squaredNorm();
  }
  row.positions = spec.positions;
  row.workspace_rms_mm = row.positions_found ? std::sqrt(sum2 / row.positions_found) : 0.0;
  row.ms_per_frame = ms.empty() ? 0.0 : UpperMedian(&ms);
  return row;
}

std::string F(double value, int digits = 4) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

}  // namespace

MarkerComparisonSpec LoadMarkerComparison(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"compare", "description", "detectors", "stereo", "static_pose", "captures",
                   "workspace", "render", "seed", "seeds", "output"});
  MarkerComparisonSpec spec;
  spec.fingerprint = FileFingerprint(path);
  const ConfigNode detectors = root["detectors"];
  for (const auto& label : detectors.Keys()) {
    const ConfigNode block = detectors[label];
    registry.CreateDetector(block["type"].AsString(), block);
    spec.detectors.emplace_back(label, block);
  }
  if (spec.detectors.empty()) {
    throw detectors.Error("lists no detector: the tables would have no rows",
                          "Give at least one, e.g. aruco: {type: aruco}");
  }
  if (root.Has("stereo")) spec.rig = ReadStereoRig(root.ResolvePath(root["stereo"].AsString()));
  spec.static_pose =
      root.Has("static_pose")
          ? ReadPose(root["static_pose"])
          : Pose{Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                 Eigen::Vector3d(0, 0, 450)};
  spec.captures = root.GetIntIn("captures", spec.captures, 2, 100000,
                                "Captures per pose: at least 2 for a sigma");
  if (root.Has("workspace")) {
    const ConfigNode w = root["workspace"];
    w.ExpectKeys({"positions", "depth_mm", "lateral_mm", "tilt_rad"});
    spec.positions = w.GetIntIn("positions", spec.positions, 1, 100000,
                                "Positions of the board in the workspace; 1 or more");
    if (w.Has("depth_mm")) {
      const auto d = w["depth_mm"].AsDoubles(2);
      spec.depth_mm = Eigen::Vector2d(d[0], d[1]);
    }
    spec.lateral_mm = w.GetDouble("lateral_mm", spec.lateral_mm);
    spec.tilt_rad = w.GetDouble("tilt_rad", spec.tilt_rad);
  }
  if (root.Has("render")) {
    const ConfigNode r = root["render"];
    r.ExpectKeys({"noise_sigma", "blur_sigma_px", "supersampling"});
    spec.render.noise_sigma = r.GetDouble("noise_sigma", spec.render.noise_sigma);
    spec.render.blur_sigma_px = r.GetDouble("blur_sigma_px", spec.render.blur_sigma_px);
    spec.render.supersampling = r.GetIntIn("supersampling", spec.render.supersampling, 1, 16,
                                           "Samples per pixel side; 1 to 16");
  }
  spec.seed = static_cast<unsigned>(root.GetInt("seed", 1));
  spec.seeds = root.GetIntIn("seeds", spec.seeds, 1, 100000,
                             "Repetitions of the comparison; 1 is the seed's alone");
  spec.output =
      root.Has("output") ? root.ResolvePath(root["output"].AsString()) : "results/markers";
  return spec;
}

std::vector<MarkerRow> CompareMarkers(const MarkerComparisonSpec& spec, Registry& registry) {
  std::vector<MarkerRow> rows;
  Progress progress("comparing detectors", static_cast<int>(spec.detectors.size()));
  for (const auto& [label, block] : spec.detectors) {
    const auto detector = registry.CreateDetector(block["type"].AsString(), block);
    rows.push_back(CompareOne(spec, label, *detector));
    progress.Advance();
  }
  return rows;
}

std::string MarkerTableMarkdown(const MarkerComparisonSpec& spec,
                                const std::vector<MarkerRow>& rows) {
  std::ostringstream out;
  out << "Stereo rig: baseline " << F(-spec.rig.T_right_left.t.x(), 1) << " mm, "
      << spec.rig.left.width << "x" << spec.rig.left.height << ", f " << F(spec.rig.left.fx, 0)
      << " px; static pose at " << F(spec.static_pose.t.z(), 0) << " mm; " << spec.captures
      << " captures; render noise " << F(spec.render.noise_sigma, 1) << " gray levels.\n\n";
  out << "| detector | sigma X (mm) | sigma Y (mm) | sigma depth (mm) | floor depth (mm) | depth / "
         "floor "
         "| bias at the static pose (mm) | workspace RMS error (mm) | detected | ms / frame |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    const double ratio = r.floor_mm.z() > 0 ? r.repeatability_mm.z() / r.floor_mm.z() : 0.0;
    out << "| " << r.label << " | " << F(r.repeatability_mm.x()) << " | "
        << F(r.repeatability_mm.y()) << " | " << F(r.repeatability_mm.z()) << " | "
        << F(r.floor_mm.z()) << " | " << F(ratio, 2) << " | " << F(r.static_bias_mm) << " | "
        << F(r.workspace_rms_mm) << " | " << r.positions_found << "/" << r.positions << " | "
        << F(r.ms_per_frame, 2) << " |\n";
  }
  return out.str();
}

std::string MarkerTableCsv(const std::vector<MarkerRow>& rows) {
  std::ostringstream out;
  out.precision(9);
  out << "detector,sigma_x_mm,sigma_y_mm,sigma_depth_mm,floor_x_mm,floor_y_mm,floor_depth_mm,"
         "static_bias_mm,workspace_rms_mm,captures_found,positions_found,positions,ms_per_frame\n";
  for (const auto& r : rows) {
    out << r.label << "," << r.repeatability_mm.x() << "," << r.repeatability_mm.y() << ","
        << r.repeatability_mm.z() << "," << r.floor_mm.x() << "," << r.floor_mm.y() << ","
        << r.floor_mm.z() << "," << r.static_bias_mm << "," << r.workspace_rms_mm << ","
        << r.captures_found << "," << r.positions_found << "," << r.positions << ","
        << r.ms_per_frame << "\n";
  }
  return out.str();
}

}  // namespace cellmetry
