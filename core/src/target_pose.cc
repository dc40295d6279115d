#include "cellmetry/target_pose.h"

#include <ceres/jet.h>

#include <opencv2/calib3d.hpp>

#include <map>

namespace cellmetry {
namespace {

using Jet6 = ceres::Jet<double, 6>;

struct Match {
  Eigen::Vector3d p_target;
  Keypoint keypoint;
};

// Residuals (weighted, 2 per point) and their Jacobian in (rvec, t).
void Evaluate(const PinholeCamera& camera, const std::vector<Match>& matches,
              const Eigen::Matrix<double, 6, 1>& x, Eigen::VectorXd* r, Eigen::MatrixXd* J) {
  Jet6 rvec[3], t[3];
  for (int i = 0; i < 3; ++i) rvec[i] = Jet6(x[i], i), t[i] = Jet6(x[3 + i], 3 + i);
  const Matrix3<Jet6> R = RotationFromRvec(rvec);
  r->resize(2 * matches.size());
  J->resize(2 * matches.size(), 6);
  for (size_t k = 0; k < matches.size(); ++k) {
    const Vector3<Jet6> p = R * matches[k].p_target.cast<Jet6>() + Vector3<Jet6>(t[0], t[1], t[2]);
    const Vector2<Jet6> px = camera.Project(p);
    // Whiten by the keypoint covariance: L^-1 (prediction - measurement), C = L L^T.
    const Eigen::Matrix2d L_inv =
        Eigen::Matrix2d(matches[k].keypoint.covariance_px2.llt().matrixL()).inverse();
    const Vector2<Jet6> e(px.x() - matches[k].keypoint.pixel.x(), px.y() - matches[k].keypoint.pixel.y());
    const Vector2<Jet6> w = L_inv.cast<Jet6>() * e;
    for (int i = 0; i < 2; ++i) {
      (*r)[2 * k + i] = w[i].a;
      J->row(2 * k + i) = w[i].v.transpose();
    }
  }
}

}  // namespace

std::optional<TargetPose> EstimateTargetPose(const PinholeCamera& camera,
                                             const std::vector<Keypoint>& keypoints,
                                             const std::vector<MarkerPoint>& layout) {
  std::map<int, Eigen::Vector3d> by_id;
  for (const auto& p : layout) by_id[p.id] = p.p_target_mm;
  std::vector<Match> matches;
  for (const auto& k : keypoints) {
    const auto it = by_id.find(k.id);
    if (it != by_id.end()) matches.push_back({it->second, k});
  }
  if (matches.size() < 4) return std::nullopt;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  bool coplanar = true;
  for (const auto& m : matches) {
    object.emplace_back(m.p_target.x(), m.p_target.y(), m.p_target.z());
    // Undistorted normalised coordinates: solvePnP then needs no distortion model.
    const Eigen::Vector3d ray = camera.Ray(m.keypoint.pixel);
    image.emplace_back(ray.x(), ray.y());
    coplanar &= std::abs(m.p_target.z()) < 1e-9;
  }
  cv::Mat rvec, tvec;
  const bool ok = cv::solvePnP(object, image, cv::Mat::eye(3, 3, CV_64F), cv::Mat(), rvec, tvec,
                               false, coplanar ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_EPNP);
  if (!ok) return std::nullopt;
  Eigen::Matrix<double, 6, 1> x;
  for (int i = 0; i < 3; ++i) x[i] = rvec.at<double>(i), x[3 + i] = tvec.at<double>(i);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  for (int iteration = 0; iteration < 20; ++iteration) {
    Evaluate(camera, matches, x, &r, &J);
    const Eigen::Matrix<double, 6, 1> step = (J.transpose() * J).ldlt().solve(-J.transpose() * r);
    x += step;
    if (step.norm() < 1e-12 * (1 + x.norm())) break;
  }
  Evaluate(camera, matches, x, &r, &J);
  TargetPose pose;
  const Eigen::Vector3d rv = x.head<3>();
  pose.T_cam_target = PoseFromRvecT(rv, x.tail<3>());
  pose.covariance = (J.transpose() * J).inverse();
  pose.reprojection_rms_px = std::sqrt(r.squaredNorm() / r.size());
  pose.points = static_cast<int>(matches.size());
  if (pose.T_cam_target.t.z() <= 0) return std::nullopt;
  return pose;
}

std::optional<TriangulatedPoint> TriangulateKeypoint(const StereoRig& rig,
                                                     const std::vector<Keypoint>& left,
                                                     const std::vector<Keypoint>& right,
                                                     int origin_id) {
  const auto find = [&](const std::vector<Keypoint>& list) -> const Keypoint* {
    for (const auto& k : list) {
      if (k.id == origin_id) return &k;
    }
    return nullptr;
  };
  const Keypoint* l = find(left);
  const Keypoint* r = find(right);
  if (!l || !r) return std::nullopt;
  return Triangulate(rig, *l, *r);
}

}  // namespace cellmetry
