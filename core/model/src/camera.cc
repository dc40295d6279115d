// PinholeCamera (camera.h): a camera read from our YAML or OpenCV's calibration output, and Ray(),
// which inverts the distortion by Newton's method.
#include "cellmetry/model/camera.h"

#include <ceres/jet.h>

#include <opencv2/core.hpp>

#include <filesystem>
#include <fstream>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

PinholeCamera FromOurYaml(const ConfigNode& root) {
  root.ExpectKeys({"camera"});
  return ReadCameraNode(root["camera"]);
}

// OpenCV's calibration output (samples/cpp/calibration.cpp): image_width, image_height,
// camera_matrix (3x3), distortion_coefficients (4, 5 or more).
PinholeCamera FromOpenCv(const std::string& path) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception&) {
    throw InputError({path, 0, 0}, "not a readable OpenCV calibration file",
                     "Give our YAML (camera: {...}) or OpenCV's calibration output");
  }
  auto require = [&](const char* key) {
    const cv::FileNode node = fs[key];
    if (node.empty()) {
      throw InputError({path, 0, 0}, std::string("missing field '") + key + "'",
                       "OpenCV calibration files need image_width, image_height, camera_matrix "
                       "and distortion_coefficients");
    }
    return node;
  };
  PinholeCamera camera;
  camera.width = static_cast<int>(require("image_width").real());
  camera.height = static_cast<int>(require("image_height").real());
  cv::Mat K, D;
  require("camera_matrix") >> K;
  require("distortion_coefficients") >> D;
  if (K.rows != 3 || K.cols != 3) {
    throw InputError({path, 0, 0}, "camera_matrix must be 3x3", "Check the calibration file");
  }
  K.convertTo(K, CV_64F);
  camera.fx = K.at<double>(0, 0);
  camera.fy = K.at<double>(1, 1);
  camera.cx = K.at<double>(0, 2);
  camera.cy = K.at<double>(1, 2);
  D.convertTo(D, CV_64F);
  const int n = static_cast<int>(D.total());
  for (int i = 0; i < n && i < 5; ++i) camera.distortion[i] = D.at<double>(i);
  for (int i = 5; i < n; ++i) {
    if (D.at<double>(i) != 0.0) {
      throw InputError({path, 0, 0}, "rational or thin-prism distortion is not supported",
                       "Calibrate with OpenCV's default 5-coefficient model");
    }
  }
  if (camera.width <= 0 || camera.height <= 0 || !(camera.fx > 0) || !(camera.fy > 0)) {
    throw InputError({path, 0, 0}, "image size and focal lengths must be positive",
                     "Check the calibration file");
  }
  return camera;
}

bool LooksLikeOpenCv(const std::string& path) {
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  return first.rfind("%YAML", 0) == 0 || first.rfind("<?xml", 0) == 0;
}

}  // namespace

PinholeCamera ReadCameraNode(const ConfigNode& c) {
  c.ExpectKeys({"width", "height", "fx", "fy", "cx", "cy", "distortion"});
  PinholeCamera camera;
  camera.width = c["width"].AsInt();
  camera.height = c["height"].AsInt();
  camera.fx = c["fx"].AsDouble();
  camera.fy = c["fy"].AsDouble();
  camera.cx = c["cx"].AsDouble();
  camera.cy = c["cy"].AsDouble();
  if (c.Has("distortion")) {
    const auto d = c["distortion"].AsDoubles();
    if (d.size() > 5) {
      throw c["distortion"].Error("at most 5 coefficients (k1 k2 p1 p2 k3) are supported",
                                  "Calibrate with OpenCV's default model");
    }
    std::copy(d.begin(), d.end(), camera.distortion.begin());
  }
  if (camera.width <= 0 || camera.height <= 0 || !(camera.fx > 0) || !(camera.fy > 0)) {
    throw c.Error("width, height, fx and fy must be positive");
  }
  return camera;
}

Eigen::Vector3d PinholeCamera::Ray(const Eigen::Vector2d& pixel) const {
  using Jet2 = ceres::Jet<double, 2>;
  const Eigen::Vector2d distorted((pixel.x() - cx) / fx, (pixel.y() - cy) / fy);
  // Newton on Distort(n) = distorted, from n = distorted; the Jacobian comes from Jets.
  Eigen::Vector2d n = distorted;
  for (int i = 0; i < 20; ++i) {
    const Vector2<Jet2> d = Distort(Vector2<Jet2>(Jet2(n.x(), 0), Jet2(n.y(), 1)));
    const Eigen::Vector2d error(d.x().a - distorted.x(), d.y().a - distorted.y());
    if (error.squaredNorm() < 1e-30) break;
    Eigen::Matrix2d J;
    J << d.x().v[0], d.x().v[1], d.y().v[0], d.y().v[1];
    n -= J.inverse() * error;
  }
  return Eigen::Vector3d(n.x(), n.y(), 1.0);
}

PinholeCamera ReadCamera(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError({path, 0, 0}, "camera calibration file not found",
                     "Give the path relative to the job file");
  }
  return LooksLikeOpenCv(path) ? FromOpenCv(path) : FromOurYaml(ConfigNode::LoadFile(path));
}

PinholeCamera OakDLikeCamera() {
  PinholeCamera camera;
  camera.width = 1280;
  camera.height = 800;
  camera.fx = camera.fy = 880.0;
  camera.cx = 639.5;
  camera.cy = 399.5;
  return camera;
}

}  // namespace cellmetry
