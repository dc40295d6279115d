// Camera calibration files (camera_file.h): ours, OpenCV's FileStorage and ROS camera_info.
#include "cellmetry/model/camera_file.h"

#include <opencv2/core.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

PinholeCamera FromOurYaml(const ConfigNode& root) {
  root.ExpectKeys({"camera"});
  return ReadCameraNode(root["camera"]);
}

const char* const kOpenCvFields =
    "OpenCV calibration files need image_width, image_height, camera_matrix and "
    "distortion_coefficients";

cv::FileNode RequireField(const cv::FileStorage& fs, const std::string& path, const char* key) {
  const cv::FileNode node = fs[key];
  if (node.empty()) {
    throw InputError({path, 0, 0}, std::string("missing field '") + key + "'", kOpenCvFields);
  }
  return node;
}

// image_width or image_height: a whole number of pixels.
int ImageSize(const cv::FileNode& node, const std::string& path, const char* key) {
  const double pixels = node.isInt() || node.isReal() ? node.real() : 0.0;
  if (!(pixels >= 1 && pixels <= 100000) || pixels != std::floor(pixels)) {
    throw InputError({path, 0, 0}, std::string("'") + key + "' is not a whole number of pixels",
                     "Write the image size in pixels, 1 to 100000");
  }
  return static_cast<int>(pixels);
}

// camera_matrix or distortion_coefficients: a one-channel matrix of finite numbers, as doubles.
// Its size is checked before OpenCV reads it: OpenCV allocates whatever rows x cols says and
// asserts (cv::Exception) when the data does not fill it, a fault of the user's file that is an
// InputError naming the field here. Neither matrix is larger than 16 in either direction.
cv::Mat FiniteMatrix(const cv::FileNode& node, const std::string& path, const char* key) {
  const std::string hint =
      "Write it as OpenCV does: !!opencv-matrix with rows, cols, dt and rows x cols numbers";
  const auto dimension = [&](const char* name) {
    const cv::FileNode n = node.isMap() ? node[name] : cv::FileNode();
    const int value = n.isInt() ? static_cast<int>(n) : 0;
    if (value < 1 || value > 16) {
      throw InputError({path, 0, 0}, std::string("'") + key + "' has no " + name + " from 1 to 16",
                       hint);
    }
    return value;
  };
  const int rows = dimension("rows"), cols = dimension("cols");
  const cv::FileNode data = node["data"];
  if (!data.isSeq() || data.size() != static_cast<size_t>(rows * cols)) {
    throw InputError({path, 0, 0},
                     std::string("'") + key + "' does not hold rows x cols = " +
                         std::to_string(rows * cols) + " numbers in its data",
                     hint);
  }
  cv::Mat m;
  try {
    node >> m;
  } catch (const cv::Exception& e) {
    throw InputError({path, 0, 0}, std::string("'") + key + "' is not a matrix: " + e.err, hint);
  }
  if (m.empty() || m.channels() != 1) {
    throw InputError({path, 0, 0}, std::string("'") + key + "' is not a one-channel matrix", hint);
  }
  m.convertTo(m, CV_64F);
  if (!cv::checkRange(m)) {
    throw InputError({path, 0, 0}, std::string("'") + key + "' holds a number that is not finite",
                     "Check the calibration file");
  }
  return m;
}

// OpenCV's calibration output (samples/cpp/calibration.cpp): image_width, image_height,
// camera_matrix (3x3), distortion_coefficients (4, 5 or more).
PinholeCamera FromOpenCv(const std::string& path) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const std::exception&) {  // cv::Exception, and std::length_error on some bad keys
    throw InputError({path, 0, 0}, "not a readable OpenCV calibration file",
                     "Give our YAML (camera: {...}), OpenCV's calibration output or a ROS "
                     "camera_info file");
  }
  if (!fs.isOpened() || !fs.root().isMap()) {
    throw InputError({path, 0, 0}, "not an OpenCV calibration file", kOpenCvFields);
  }
  PinholeCamera camera;
  camera.width = ImageSize(RequireField(fs, path, "image_width"), path, "image_width");
  camera.height = ImageSize(RequireField(fs, path, "image_height"), path, "image_height");
  const cv::Mat K = FiniteMatrix(RequireField(fs, path, "camera_matrix"), path, "camera_matrix");
  const cv::Mat D = FiniteMatrix(RequireField(fs, path, "distortion_coefficients"), path,
                                 "distortion_coefficients");
  if (K.rows != 3 || K.cols != 3) {
    throw InputError({path, 0, 0}, "camera_matrix must be 3x3", "Check the calibration file");
  }
  camera.fx = K.at<double>(0, 0);
  camera.fy = K.at<double>(1, 1);
  camera.cx = K.at<double>(0, 2);
  camera.cy = K.at<double>(1, 2);
  const int n = static_cast<int>(D.total());
  for (int i = 0; i < n && i < 5; ++i) camera.distortion[i] = D.at<double>(i);
  for (int i = 5; i < n; ++i) {
    if (D.at<double>(i) != 0.0) {
      throw InputError({path, 0, 0}, "rational or thin-prism distortion is not supported",
                       "Calibrate with OpenCV's default 5-coefficient model");
    }
  }
  if (!(camera.fx > 0) || !(camera.fy > 0)) {
    throw InputError({path, 0, 0}, "focal lengths must be positive", "Check the calibration file");
  }
  return camera;
}

bool LooksLikeOpenCv(const std::string& path) {
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  return first.rfind("%YAML", 0) == 0 || first.rfind("<?xml", 0) == 0;
}

// A ROS matrix block {rows, cols, data}, checked against the size the field must have.
Eigen::MatrixXd RosMatrix(const ConfigNode& node, int rows, int cols) {
  node.ExpectKeys({"rows", "cols", "data"});
  const int file_rows = node["rows"].AsInt(), file_cols = node["cols"].AsInt();
  if (file_rows != rows || (cols > 0 && file_cols != cols)) {
    throw node.Error("is " + std::to_string(file_rows) + "x" + std::to_string(file_cols) +
                         ", expected " + std::to_string(rows) + "x" +
                         (cols > 0 ? std::to_string(cols) : std::string("n")),
                     "Check the camera_info file");
  }
  const std::vector<double> data = node["data"].AsDoubles(file_rows * file_cols);
  Eigen::MatrixXd m(file_rows, file_cols);
  for (int r = 0; r < file_rows; ++r) {
    for (int c = 0; c < file_cols; ++c) m(r, c) = data[r * file_cols + c];
  }
  return m;
}

// plumb_bob is OpenCV's k1 k2 p1 p2 k3; rational_polynomial adds k4 k5 k6, accepted when zero.
void ReadRosDistortion(const ConfigNode& root, PinholeCamera* camera) {
  const std::string model = root.GetString("distortion_model", "plumb_bob");
  if (model != "plumb_bob" && model != "rational_polynomial") {
    throw root["distortion_model"].Error(
        "distortion model '" + model + "' is not supported",
        "cellmetry models OpenCV's 5-coefficient distortion: calibrate with plumb_bob");
  }
  if (!root.Has("distortion_coefficients")) return;  // no distortion
  const ConfigNode node = root["distortion_coefficients"];
  const Eigen::MatrixXd D = RosMatrix(node, 1, -1);
  for (int i = 0; i < D.cols() && i < 5; ++i) camera->distortion[i] = D(0, i);
  for (int i = 5; i < D.cols(); ++i) {
    if (D(0, i) != 0.0) {
      throw node.Error("coefficient k" + std::to_string(i - 1) + " is not zero",
                       "rational distortion (k4 k5 k6) is not supported: calibrate with "
                       "plumb_bob");
    }
  }
}

}  // namespace

bool IsRosCameraInfo(const ConfigNode& root) {
  return root.IsMap() && root.Has("camera_matrix") && root.Has("image_width");
}

RosCameraInfo ReadRosCameraInfo(const ConfigNode& root) {
  root.ExpectKeys({"image_width", "image_height", "camera_name", "camera_matrix",
                   "distortion_model", "distortion_coefficients", "rectification_matrix",
                   "projection_matrix", "binning_x", "binning_y"});
  for (const char* key : {"image_width", "image_height", "camera_matrix"}) {
    if (!root.Has(key)) {
      throw root.Error(std::string("missing field '") + key + "'",
                       "A ROS camera_info file has image_width, image_height and camera_matrix");
    }
  }
  RosCameraInfo info;
  PinholeCamera& camera = info.camera;
  camera.width = root.GetIntIn("image_width", 0, 1, 100000, "the image width in pixels");
  camera.height = root.GetIntIn("image_height", 0, 1, 100000, "the image height in pixels");
  const Eigen::MatrixXd K = RosMatrix(root["camera_matrix"], 3, 3);
  camera.fx = K(0, 0), camera.fy = K(1, 1), camera.cx = K(0, 2), camera.cy = K(1, 2);
  if (!(camera.fx > 0) || !(camera.fy > 0) || K(0, 1) != 0.0 || K(2, 2) != 1.0) {
    throw root["camera_matrix"].Error(
        "is not a camera matrix [fx 0 cx; 0 fy cy; 0 0 1] with "
        "positive focal lengths",
        "Check the camera_info file");
  }
  ReadRosDistortion(root, &camera);
  if (root.Has("rectification_matrix")) {
    info.R_rect_camera = RosMatrix(root["rectification_matrix"], 3, 3);
  }
  if (root.Has("projection_matrix")) info.P = RosMatrix(root["projection_matrix"], 3, 4);
  for (const char* key : {"binning_x", "binning_y"}) {
    if (root.GetInt(key, 0) > 1) {
      throw root[key].Error("binned images are not supported",
                            "Calibrate and record at full resolution (binning 0 or 1)");
    }
  }
  return info;
}

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

PinholeCamera ReadCamera(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError({path, 0, 0}, "camera calibration file not found",
                     "Give the path relative to the job file");
  }
  if (LooksLikeOpenCv(path)) return FromOpenCv(path);
  const ConfigNode root = ConfigNode::LoadFile(path);
  if (IsRosCameraInfo(root)) return ReadRosCameraInfo(root).camera;
  return FromOurYaml(root);
}

}  // namespace cellmetry
