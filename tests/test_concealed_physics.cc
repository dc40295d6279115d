// Concealed physics that acts in a camera (concealed_physics.h, lens_distortion): what a pose
// estimator with a wrong distortion model makes of a board, checked against its own definition
// (the distorted ray; the depth from the map's local stretch, by central differences) and
// against the library's radial k1 form it generalizes.
#include <gtest/gtest.h>

#include <cmath>

#include "cellmetry/experiments/concealed_physics.h"

namespace cellmetry {
namespace {

ConcealedPhysics Lens(double magnitude) {
  ConcealedPhysics lens;
  lens.kind = "lens_distortion";
  lens.camera = "cam1";
  lens.magnitude = magnitude;
  return lens;
}

Pose BoardAt(double x, double y, double z) {
  Pose T;
  T.t = Eigen::Vector3d(x * z, y * z, z);
  T.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  return T;
}

// The ray a board at normalized image coordinates (x, y) is seen along.
Eigen::Vector2d SeenRay(const ConcealedPhysics& lens, double x, double y) {
  Pose T = BoardAt(x, y, 900.0);
  lens.MeasureInCamera("cam1", &T);
  return T.t.head<2>() / T.t.z();
}

TEST(LensDistortion, PutsTheBoardWhereTheDistortionsStretchSaysPnPWould) {
  const ConcealedPhysics lens = Lens(0.05);
  for (const auto& [x, y] : {std::pair{0.3, 0.2}, {-0.45, 0.1}, {0.05, -0.35}}) {
    Pose T = BoardAt(x, y, 900.0);
    const Eigen::Matrix3d R = T.R;
    lens.MeasureInCamera("cam1", &T);
    // The ray: Brown-Conrady with k1 = m, k2 = -0.4 m, p1 = 0.2 m, p2 = -0.1 m, written out.
    const double m = 0.05, r2 = x * x + y * y, radial = m * r2 - 0.4 * m * r2 * r2;
    const Eigen::Vector2d ray(x * (1 + radial) + 0.4 * m * x * y - 0.1 * m * (r2 + 2 * x * x),
                              y * (1 + radial) + 0.2 * m * (r2 + 2 * y * y) - 0.2 * m * x * y);
    EXPECT_LT((T.t.head<2>() / T.t.z() - ray).norm(), 1e-12);
    // The depth: the map's local area stretch, its Jacobian by central differences.
    const double h = 1e-6;
    Eigen::Matrix2d J;
    J.col(0) = (SeenRay(lens, x + h, y) - SeenRay(lens, x - h, y)) / (2 * h);
    J.col(1) = (SeenRay(lens, x, y + h) - SeenRay(lens, x, y - h)) / (2 * h);
    EXPECT_NEAR(T.t.z(), 900.0 / std::sqrt(J.determinant()), 1e-6) << x << ", " << y;
    EXPECT_TRUE(T.R.isApprox(R, 1e-15)) << "the rotation is left as it is";
  }
}

TEST(LensDistortion, WithK1AloneIsTheLibrarysRadialFormToFirstOrder) {
  // camera_intrinsics' radial term: x' = x (1 + k r^2), Z' = Z (1 - 2 k r^2), to first order.
  ConcealedPhysics lens = Lens(1e-3);
  lens.lens_shape.setZero();
  const double k = 1e-3;
  for (const auto& [x, y] : {std::pair{0.3, 0.2}, {-0.45, 0.1}}) {
    Pose T = BoardAt(x, y, 1000.0);
    lens.MeasureInCamera("cam1", &T);
    const double r2 = x * x + y * y;
    EXPECT_NEAR(T.t.z(), 1000.0 * (1.0 - 2.0 * k * r2), 1000.0 * 10.0 * k * k);
    EXPECT_NEAR(T.t.x() / T.t.z(), x * (1.0 + k * r2), 1e-15);
  }
  // The default shape adds tangential terms, first order in the image position: not radial.
  Pose T = BoardAt(0.3, 0.2, 1000.0);
  Lens(1e-3).MeasureInCamera("cam1", &T);
  EXPECT_GT(std::abs(T.t.z() - 1000.0 * (1.0 - 2.0 * k * 0.13)), 1000.0 * 10.0 * k * k);
}

TEST(LensDistortion, LeavesOtherCamerasAndOtherKindsAlone) {
  const Pose before = BoardAt(0.3, 0.2, 800.0);
  Pose other_camera = before;
  Lens(0.05).MeasureInCamera("cam2", &other_camera);
  EXPECT_EQ(other_camera.t, before.t);
  ConcealedPhysics bump = Lens(0.05);
  bump.kind = "camera_bump";
  Pose bumped = before;
  bump.MeasureInCamera("cam1", &bumped);
  EXPECT_EQ(bumped.t, before.t);
}

}  // namespace
}  // namespace cellmetry
