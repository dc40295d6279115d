// The rendering simulator (render.h): marker faces ray traced with supersampling, then light
// falloff, blur, noise and quantisation; the exact keypoints and the image-shift Cramer-Rao bound.
#include "cellmetry/imaging/render.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cellmetry {
namespace {

struct FaceInCamera {
  Pose T_cam_face;
  Pose T_face_cam;
  const MarkerFace* face = nullptr;
  double width_mm = 0.0, height_mm = 0.0;
};

double SampleTexture(const MarkerFace& face, double u_mm, double v_mm) {
  const GrayImage& t = face.texture;
  const double x = u_mm / face.mm_per_texel - 0.5, y = v_mm / face.mm_per_texel - 0.5;
  const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, t.width() - 1);
  const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, t.height() - 1);
  const int x1 = std::min(x0 + 1, t.width() - 1), y1 = std::min(y0 + 1, t.height() - 1);
  const double ax = std::clamp(x - x0, 0.0, 1.0), ay = std::clamp(y - y0, 0.0, 1.0);
  const double top = (1 - ax) * t.at(x0, y0) + ax * t.at(x1, y0);
  const double bottom = (1 - ax) * t.at(x0, y1) + ax * t.at(x1, y1);
  return (1 - ay) * top + ay * bottom;
}

// Pixel box around a face's projection (corners and edge points), clipped; empty if unseen.
cv::Rect FaceBox(const PinholeCamera& camera, const FaceInCamera& f, int margin) {
  double x0 = 1e30, y0 = 1e30, x1 = -1e30, y1 = -1e30;
  for (int i = 0; i <= 8; ++i) {
    for (int j = 0; j <= 8; ++j) {
      if (i != 0 && i != 8 && j != 0 && j != 8) continue;  // the border only
      const Eigen::Vector3d p =
          f.T_cam_face * Eigen::Vector3d(f.width_mm * i / 8, f.height_mm * j / 8, 0);
      if (p.z() <= 1e-6) return {};
      const Eigen::Vector2d px = camera.Project(p);
      x0 = std::min(x0, px.x()), y0 = std::min(y0, px.y());
      x1 = std::max(x1, px.x()), y1 = std::max(y1, px.y());
    }
  }
  const cv::Rect box(static_cast<int>(std::floor(x0)) - margin,
                     static_cast<int>(std::floor(y0)) - margin,
                     static_cast<int>(std::ceil(x1 - x0)) + 2 * margin + 1,
                     static_cast<int>(std::ceil(y1 - y0)) + 2 * margin + 1);
  return box & cv::Rect(0, 0, camera.width, camera.height);
}

// Texture value (0..255) seen along `ray` (camera frame), or -1 if no face is hit.
double Trace(const Eigen::Vector3d& ray, const std::vector<FaceInCamera>& faces) {
  double nearest = 1e300, value = -1.0;
  for (const auto& f : faces) {
    const Eigen::Vector3d n = f.T_cam_face.R.col(2);
    const double denom = n.dot(ray);
    if (std::abs(denom) < 1e-12) continue;
    const double t = n.dot(f.T_cam_face.t) / denom;
    if (t <= 0 || t >= nearest) continue;
    const Eigen::Vector3d local = f.T_face_cam * (t * ray);
    if (local.x() < 0 || local.y() < 0 || local.x() >= f.width_mm || local.y() >= f.height_mm) {
      continue;
    }
    nearest = t;
    value = SampleTexture(*f.face, local.x(), local.y());
  }
  return value;
}

}  // namespace

std::vector<float> RenderIdeal(const PinholeCamera& camera,
                               const std::vector<PlacedTarget>& targets,
                               const RenderOptions& options) {
  std::vector<FaceInCamera> faces;
  for (const auto& target : targets) {
    for (const auto& face : *target.faces) {
      FaceInCamera f;
      f.T_cam_face = target.T_cam_target * face.T_target_face;
      f.T_face_cam = f.T_cam_face.inverse();
      f.face = &face;
      f.width_mm = face.texture.width() * face.mm_per_texel;
      f.height_mm = face.texture.height() * face.mm_per_texel;
      // Paper seen from behind is not seen: its normal must face the camera.
      if (f.T_cam_face.R.col(2).dot(-f.T_cam_face.t) <= 0) continue;
      faces.push_back(f);
    }
  }
  cv::Mat image(camera.height, camera.width, CV_32F, cv::Scalar(options.background));
  cv::Mat done(camera.height, camera.width, CV_8U, cv::Scalar(0));
  const int S = std::max(1, options.supersampling);
  const int margin = 2 + static_cast<int>(std::ceil(3 * options.blur_sigma_px));
  const double scale = (options.white - options.black) / 255.0;
  for (const auto& f : faces) {
    const cv::Rect box = FaceBox(camera, f, margin);
    for (int y = box.y; y < box.y + box.height; ++y) {
      for (int x = box.x; x < box.x + box.width; ++x) {
        if (done.at<std::uint8_t>(y, x)) continue;
        done.at<std::uint8_t>(y, x) = 1;
        double sum = 0.0;
        for (int sy = 0; sy < S; ++sy) {
          for (int sx = 0; sx < S; ++sx) {
            const Eigen::Vector2d sub(x - 0.5 + (sx + 0.5) / S, y - 0.5 + (sy + 0.5) / S);
            const double texel = Trace(camera.Ray(sub), faces);
            sum += texel < 0 ? options.background : options.black + scale * texel;
          }
        }
        image.at<float>(y, x) = static_cast<float>(sum / (S * S));
      }
    }
  }
  // Light falls off linearly across the frame; then optics and sensor blur.
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const double light = 1.0 +
                           options.illumination_gradient.x() * (x - camera.cx) / camera.width +
                           options.illumination_gradient.y() * (y - camera.cy) / camera.height;
      image.at<float>(y, x) *= static_cast<float>(light);
    }
  }
  if (options.blur_sigma_px > 0) {
    cv::GaussianBlur(image, image, cv::Size(0, 0), options.blur_sigma_px, options.blur_sigma_px,
                     cv::BORDER_REPLICATE);
  }
  return std::vector<float>(image.begin<float>(), image.end<float>());
}

GrayImage SensorImage(const std::vector<float>& ideal, int width, int height,
                      const RenderOptions& options, std::mt19937& rng) {
  if (ideal.size() != static_cast<size_t>(width) * height) {
    throw std::invalid_argument("SensorImage: the ideal image has " + std::to_string(ideal.size()) +
                                " pixels, not " + std::to_string(width) + " x " +
                                std::to_string(height));
  }
  std::normal_distribution<double> noise(0.0, options.noise_sigma);
  GrayImage image(width, height);
  for (size_t i = 0; i < ideal.size(); ++i) {
    const double value = ideal[i] + (options.noise_sigma > 0 ? noise(rng) : 0.0);
    image.data()[i] = static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
  }
  return image;
}

GrayImage RenderView(const PinholeCamera& camera, const std::vector<PlacedTarget>& targets,
                     const RenderOptions& options, std::mt19937& rng) {
  return SensorImage(RenderIdeal(camera, targets, options), camera.width, camera.height, options,
                     rng);
}

std::vector<Keypoint> ProjectLayout(const PinholeCamera& camera, const Pose& T_cam_target,
                                    const std::vector<MarkerPoint>& layout) {
  std::vector<Keypoint> out;
  for (const auto& point : layout) {
    const Eigen::Vector3d p = T_cam_target * point.p_target_mm;
    if (p.z() <= 0) continue;
    Keypoint k;
    k.id = point.id;
    k.pixel = camera.Project(p);
    k.covariance_px2.setZero();
    out.push_back(k);
  }
  return out;
}

Eigen::Vector2d ImageShiftCramerRao(const std::vector<float>& ideal, int width, int height,
                                    double noise_sigma) {
  double fxx = 0.0, fyy = 0.0;
  for (int y = 1; y + 1 < height; ++y) {
    for (int x = 1; x + 1 < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      const double gx = 0.5 * (ideal[i + 1] - ideal[i - 1]);
      const double gy = 0.5 * (ideal[i + width] - ideal[i - width]);
      fxx += gx * gx;
      fyy += gy * gy;
    }
  }
  const double n2 = noise_sigma * noise_sigma;
  return Eigen::Vector2d(std::sqrt(n2 / fxx), std::sqrt(n2 / fyy));
}

}  // namespace cellmetry
