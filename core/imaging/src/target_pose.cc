// Target poses from keypoints (target_pose.h): PnP started by OpenCV, finished by weighted
// Gauss-Newton with outliers dropped; a target's origin from stereo triangulation.
#include "cellmetry/imaging/target_pose.h"

#include <ceres/jet.h>

#include <opencv2/calib3d.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <map>

#include "cellmetry/basics/rigid_fit.h"

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
    const Vector2<Jet6> e(px.x() - matches[k].keypoint.pixel.x(),
                          px.y() - matches[k].keypoint.pixel.y());
    const Vector2<Jet6> w = L_inv.cast<Jet6>() * e;
    for (int i = 0; i < 2; ++i) {
      (*r)[2 * k + i] = w[i].a;
      J->row(2 * k + i) = w[i].v.transpose();
    }
  }
}

// Gauss-Newton from x to the minimum of the whitened reprojection error.
void Refine(const PinholeCamera& camera, const std::vector<Match>& matches,
            Eigen::Matrix<double, 6, 1>* x) {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  for (int iteration = 0; iteration < 20; ++iteration) {
    Evaluate(camera, matches, *x, &r, &J);
    const Eigen::Matrix<double, 6, 1> step = (J.transpose() * J).ldlt().solve(-J.transpose() * r);
    *x += step;
    if (step.norm() < 1e-12 * (1 + x->norm())) break;
  }
}

// The frame of the plane the points lie in (z = 0 there), when they are coplanar: IPPE then
// starts the pose (a cube's one visible face is coplanar, but not in the target's z = 0).
std::optional<Pose> PlaneFrame(const std::vector<Match>& matches) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& m : matches) mean += m.p_target;
  mean /= static_cast<double>(matches.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& m : matches) scatter += (m.p_target - mean) * (m.p_target - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  if (eigen.eigenvalues()[0] > 1e-12 * eigen.eigenvalues()[2]) return std::nullopt;
  Eigen::Matrix3d R = eigen.eigenvectors();  // columns: normal first, then in-plane axes
  R = (Eigen::Matrix3d() << R.col(1), R.col(2), R.col(1).cross(R.col(2))).finished();
  return Pose{R, mean};  // T_target_plane
}

// OpenCV's start: IPPE in the points' plane when they are coplanar, else EPnP.
std::optional<Eigen::Matrix<double, 6, 1>> StartPose(const PinholeCamera& camera,
                                                     const std::vector<Match>& matches) {
  const std::optional<Pose> T_target_plane = PlaneFrame(matches);
  const Pose T_plane_target = T_target_plane ? T_target_plane->inverse() : Pose::Identity();
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const auto& m : matches) {
    const Eigen::Vector3d p = T_plane_target * m.p_target;
    object.emplace_back(p.x(), p.y(), T_target_plane ? 0.0 : p.z());
    // Undistorted normalised coordinates: solvePnP then needs no distortion model.
    const Eigen::Vector3d ray = camera.Ray(m.keypoint.pixel);
    image.emplace_back(ray.x(), ray.y());
  }
  cv::Mat rvec, tvec;
  if (!cv::solvePnP(object, image, cv::Mat::eye(3, 3, CV_64F), cv::Mat(), rvec, tvec, false,
                    T_target_plane ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_EPNP)) {
    return std::nullopt;
  }
  Eigen::Vector3d rv, t;
  for (int i = 0; i < 3; ++i) rv[i] = rvec.at<double>(i), t[i] = tvec.at<double>(i);
  const Pose T_cam_target = PoseFromRvecT(rv, t) * T_plane_target;
  Eigen::Matrix<double, 6, 1> x;
  x << RvecFromRotation(T_cam_target.R), T_cam_target.t;
  return x;
}

// Whitened squared reprojection error of each match (chi-square, 2 dof).
std::vector<double> PointChi2(const PinholeCamera& camera, const std::vector<Match>& matches,
                              const Eigen::Matrix<double, 6, 1>& x) {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  Evaluate(camera, matches, x, &r, &J);
  std::vector<double> chi2(matches.size());
  for (size_t k = 0; k < matches.size(); ++k) chi2[k] = r.segment<2>(2 * k).squaredNorm();
  return chi2;
}

}  // namespace

std::optional<TargetPose> EstimateTargetPose(const PinholeCamera& camera,
                                             const std::vector<Keypoint>& keypoints,
                                             const std::vector<MarkerPoint>& layout,
                                             const PoseEstimationOptions& options) {
  std::map<int, Eigen::Vector3d> by_id;
  for (const auto& p : layout) by_id[p.id] = p.p_target_mm;
  std::vector<Match> matches;
  for (const auto& k : keypoints) {
    const auto it = by_id.find(k.id);
    if (it != by_id.end()) matches.push_back({it->second, k});
  }
  if (matches.size() < 4) return std::nullopt;
  auto start = StartPose(camera, matches);
  if (!start) return std::nullopt;
  Eigen::Matrix<double, 6, 1> x = *start;
  Refine(camera, matches, &x);
  TargetPose pose;
  // A keypoint the pose cannot explain (a corner of a partly hidden tag, a grazing view) is
  // dropped, worst first, while more than 4 remain, and the pose refitted.
  while (static_cast<int>(matches.size()) > options.min_points) {
    const std::vector<double> chi2 = PointChi2(camera, matches, x);
    const auto worst = std::max_element(chi2.begin(), chi2.end());
    if (*worst <= options.outlier_chi2) break;
    matches.erase(matches.begin() + (worst - chi2.begin()));
    ++pose.rejected;
    Refine(camera, matches, &x);
  }
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  Evaluate(camera, matches, x, &r, &J);
  pose.T_cam_target = PoseFromRvecT(Eigen::Vector3d(x.head<3>()), x.tail<3>());
  pose.normalized_reprojection_rms = std::sqrt(r.squaredNorm() / r.size());
  pose.points = static_cast<int>(matches.size());
  // (J^T W J)^-1 assumes the keypoints' covariances are right; when the residuals say they are
  // larger, the covariance grows by the a-posteriori variance factor (never shrinks).
  const int dof = static_cast<int>(r.size()) - 6;
  pose.variance_factor = dof > 0 ? std::max(1.0, r.squaredNorm() / dof) : 1.0;
  pose.covariance = pose.variance_factor * (J.transpose() * J).inverse();
  if (pose.T_cam_target.t.z() <= 0) return std::nullopt;
  return pose;
}

std::optional<TriangulatedPoint> TargetOriginFromStereo(const StereoRig& rig,
                                                        const std::vector<Keypoint>& left,
                                                        const std::vector<Keypoint>& right,
                                                        const std::vector<MarkerPoint>& layout,
                                                        int origin_id) {
  std::map<int, const Keypoint*> in_right;
  for (const auto& k : right) in_right[k.id] = &k;
  std::map<int, Eigen::Vector3d> by_id;
  for (const auto& p : layout) by_id[p.id] = p.p_target_mm;
  const auto origin = by_id.find(origin_id);
  if (origin != by_id.end() && origin->second.norm() < 1e-9) {
    for (const auto& k : left) {
      if (k.id == origin_id && in_right.count(k.id)) return Triangulate(rig, k, *in_right[k.id]);
    }
  }
  std::vector<Eigen::Vector3d> from, to;
  Eigen::Matrix3d covariance_sum = Eigen::Matrix3d::Zero();
  double error2 = 0.0;
  for (const auto& k : left) {
    const auto r = in_right.find(k.id);
    const auto p = by_id.find(k.id);
    if (r == in_right.end() || p == by_id.end()) continue;
    const auto point = Triangulate(rig, k, *r->second);
    if (!point) continue;
    from.push_back(p->second);
    to.push_back(point->p_left_mm);
    covariance_sum += point->covariance_mm2;
    error2 += point->reprojection_rms_px * point->reprojection_rms_px;
  }
  if (from.size() < 3) return std::nullopt;
  const auto fit = FitRigidTransform(from, to);
  if (!fit) return std::nullopt;
  TriangulatedPoint out;
  out.p_left_mm = fit->t;
  const double n = static_cast<double>(from.size());
  out.covariance_mm2 = covariance_sum / (n * n);
  out.reprojection_rms_px = std::sqrt(error2 / n);
  return out;
}

}  // namespace cellmetry
