// Camera intrinsics from board views (camera_calibration.h): detect, match to the layout by id,
// calibrateCamera, and the camera file with the figures as comments.
#include "cellmetry/imaging/camera_calibration.h"

#include <opencv2/calib3d.hpp>

#include <cmath>
#include <cstdio>
#include <map>

#include "cellmetry/basics/error.h"
#include "cellmetry/formats/image.h"

namespace cellmetry {
namespace {

constexpr double kFlat = 1e-9;  // mm: a layout point further than this from z = 0 is not flat

std::string Number(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.10g", value);
  return text;
}

}  // namespace

const std::array<const char*, 9>& IntrinsicNames() {
  static const std::array<const char*, 9> names = {"fx", "fy", "cx", "cy", "k1",
                                                   "k2", "p1", "p2", "k3"};
  return names;
}

std::array<double, 9> IntrinsicValues(const PinholeCamera& k) {
  return {k.fx,
          k.fy,
          k.cx,
          k.cy,
          k.distortion[0],
          k.distortion[1],
          k.distortion[2],
          k.distortion[3],
          k.distortion[4]};
}

namespace {

// The board's points by id, on z = 0: calibrateCamera's model is a flat board.
std::map<int, cv::Point3f> FlatLayout(const Detector& detector,
                                      const CameraCalibrationOptions& options) {
  std::map<int, cv::Point3f> layout;
  for (const MarkerPoint& p : detector.layout()) {
    if (std::abs(p.p_target_mm.z()) > kFlat) {
      throw InputError(options.detector_at,
                       "calibrate-camera needs a flat board (layout z = 0); point " +
                           std::to_string(p.id) + " is at z = " + Number(p.p_target_mm.z()) + " mm",
                       "Use a board detector such as checkerboard or charuco");
    }
    layout[p.id] = cv::Point3f(static_cast<float>(p.p_target_mm.x()),
                               static_cast<float>(p.p_target_mm.y()), 0.f);
  }
  return layout;
}

// The views calibrateCamera is given: each the board's points and where they were seen.
struct BoardViews {
  std::vector<std::vector<cv::Point3f>> objects;
  std::vector<std::vector<cv::Point2f>> pixels;
  cv::Size size;  // the first view's; views of another size are left out
};

// One image's view of the board, added to `views` and `out->views`; or the reason it is not,
// in `out->skipped`.
void AddView(const std::string& path, Detector& detector, const std::map<int, cv::Point3f>& layout,
             const CameraCalibrationOptions& options, BoardViews* views, CameraCalibration* out) {
  GrayImage image;
  try {
    image = ReadGrayImage(path);
  } catch (const InputError& e) {
    out->skipped.emplace_back(path, e.message());
    return;
  }
  const Detection detection = detector.Detect(image.view());
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> pixels;
  for (const Keypoint& k : detection.keypoints) {
    const auto it = layout.find(k.id);
    if (it == layout.end()) continue;
    object.push_back(it->second);
    pixels.emplace_back(static_cast<float>(k.pixel.x()), static_cast<float>(k.pixel.y()));
  }
  if (static_cast<int>(object.size()) < options.min_keypoints) {
    out->skipped.emplace_back(path, detection.found() ? std::to_string(object.size()) +
                                                            " keypoints, fewer than " +
                                                            std::to_string(options.min_keypoints)
                                                      : detection.failure);
    return;
  }
  // One camera, one image size: the first view that shows the board sets it (an image of
  // another size among the views, such as a photograph that is not of the board, is not it).
  cv::Size& size = views->size;
  if (size.area() == 0) size = cv::Size(image.width(), image.height());
  if (image.width() != size.width || image.height() != size.height) {
    out->skipped.emplace_back(path, "the image is " + std::to_string(image.width()) + " x " +
                                        std::to_string(image.height()) + ", the first view was " +
                                        std::to_string(size.width) + " x " +
                                        std::to_string(size.height));
    return;
  }
  views->objects.push_back(std::move(object));
  views->pixels.push_back(std::move(pixels));
  out->views.push_back({path, static_cast<int>(views->pixels.back().size()), 0.0});
}

void RequireThreeViews(const CameraCalibration& out, size_t num_images,
                       const CameraCalibrationOptions& options) {
  if (out.views.size() >= 3) return;
  std::string why;  // the first few images left out, and why
  for (size_t i = 0; i < out.skipped.size() && i < 3; ++i) {
    why += (i == 0 ? " (" : "; ") + out.skipped[i].first + ": " + out.skipped[i].second;
  }
  if (!why.empty()) why += out.skipped.size() > 3 ? "; ...)" : ")";
  throw InputError(options.detector_at,
                   "calibrate-camera found the board in " + std::to_string(out.views.size()) +
                       " of " + std::to_string(num_images) + " images; it needs 3 or more" + why,
                   "Check the detector's options against the board, and give views of the "
                   "board tilted different ways");
}

// OpenCV's calibrateCamera (Zhang's method refined by Levenberg-Marquardt) over the views; its
// intrinsics, their standard deviations and each view's reprojection RMS into `out`.
void SolveIntrinsics(const BoardViews& views, const CameraCalibrationOptions& options,
                     CameraCalibration* out) {
  int flags = 0;
  if (options.fix_aspect_ratio) flags |= cv::CALIB_FIX_ASPECT_RATIO;
  if (options.zero_tangential) flags |= cv::CALIB_ZERO_TANGENT_DIST;
  if (options.fix_k3) flags |= cv::CALIB_FIX_K3;
  cv::Mat K = cv::Mat::eye(3, 3, CV_64F), dist = cv::Mat::zeros(5, 1, CV_64F);
  cv::Mat sigma_intrinsics, sigma_extrinsics, per_view;
  std::vector<cv::Mat> rvecs, tvecs;
  out->rms_px = cv::calibrateCamera(views.objects, views.pixels, views.size, K, dist, rvecs, tvecs,
                                    sigma_intrinsics, sigma_extrinsics, per_view, flags);
  PinholeCamera& camera = out->camera;
  camera.width = views.size.width;
  camera.height = views.size.height;
  camera.fx = K.at<double>(0, 0);
  camera.fy = K.at<double>(1, 1);
  camera.cx = K.at<double>(0, 2);
  camera.cy = K.at<double>(1, 2);
  for (int i = 0; i < 5; ++i) camera.distortion[i] = dist.at<double>(i);
  for (int i = 0; i < 9; ++i) out->sigma[i] = sigma_intrinsics.at<double>(i);
  // With the aspect ratio held, OpenCV fits fy alone and reports 0 for fx = ratio * fy.
  if (options.fix_aspect_ratio) out->sigma[0] = out->sigma[1] * camera.fx / camera.fy;
  for (size_t v = 0; v < out->views.size(); ++v) out->views[v].rms_px = per_view.at<double>(v);
}

}  // namespace

CameraCalibration CalibrateCamera(Detector& detector, const std::vector<std::string>& image_paths,
                                  const CameraCalibrationOptions& options) {
  const std::map<int, cv::Point3f> layout = FlatLayout(detector, options);
  CameraCalibration out;
  BoardViews views;
  for (const std::string& path : image_paths) {
    AddView(path, detector, layout, options, &views, &out);
  }
  RequireThreeViews(out, image_paths.size(), options);
  SolveIntrinsics(views, options, &out);
  return out;
}

std::string CameraFileText(const CameraCalibration& c) {
  std::string text = "# cellmetry calibrate-camera: " + std::to_string(c.views.size()) +
                     " views, reprojection RMS " + Number(c.rms_px) + " px\n";
  text += "# standard deviations:";
  for (int i = 0; i < 9; ++i)
    text += std::string(" ") + IntrinsicNames()[i] + " " + Number(c.sigma[i]);
  text += "\n# per view (keypoints, RMS px):\n";
  for (const CalibrationView& v : c.views) {
    text += "#   " + v.path + ": " + std::to_string(v.keypoints) + ", " + Number(v.rms_px) + "\n";
  }
  for (const auto& [path, why] : c.skipped) text += "#   " + path + ": left out, " + why + "\n";
  const PinholeCamera& k = c.camera;
  text += "camera: {width: " + std::to_string(k.width) + ", height: " + std::to_string(k.height) +
          ", fx: " + Number(k.fx) + ", fy: " + Number(k.fy) + ", cx: " + Number(k.cx) +
          ", cy: " + Number(k.cy) + ",\n         distortion: [";
  for (int i = 0; i < 5; ++i) text += (i ? ", " : "") + Number(k.distortion[i]);
  text += "]}\n";
  return text;
}

}  // namespace cellmetry
