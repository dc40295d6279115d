// Concealed physics (concealed_physics.h). In a camera (lens_distortion): what a pose estimator
// with a wrong distortion model makes of a board, checked against its own definition (the
// distorted ray; the depth from the map's local stretch and the turn from its local rotation, by
// central differences) and against the library's lens form (camera_intrinsics) it goes beyond.
// In a joint (gravity_backlash): play held by gravity beyond the friction, by the last move
// within it.
#include <gtest/gtest.h>

#include <cmath>

#include "cellmetry/experiments/concealed_physics.h"
#include "cellmetry/model/effect_context.h"
#include "support/test_support.h"

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
  ConcealedPhysics lens = Lens(0.05);
  lens.lens_beyond = Eigen::Vector3d(0.3, 0.1, -0.1);
  for (const auto& [x, y] : {std::pair{0.3, 0.2}, {-0.45, 0.1}, {0.05, -0.35}}) {
    Pose T = BoardAt(x, y, 900.0);
    const Eigen::Matrix3d R = T.R;
    lens.MeasureInCamera("cam1", &T);
    // The ray: k1 = m, k2 = -0.4 m, k3 = 0.3 m, p1 = 0.2 m, p2 = -0.1 m, s1 = 0.1 m,
    // s3 = -0.1 m, written out.
    const double m = 0.05, r2 = x * x + y * y;
    const double radial = m * r2 - 0.4 * m * r2 * r2 + 0.3 * m * r2 * r2 * r2;
    const Eigen::Vector2d ray(
        x * (1 + radial) + 0.4 * m * x * y - 0.1 * m * (r2 + 2 * x * x) + 0.1 * m * r2,
        y * (1 + radial) + 0.2 * m * (r2 + 2 * y * y) - 0.2 * m * x * y - 0.1 * m * r2);
    EXPECT_LT((T.t.head<2>() / T.t.z() - ray).norm(), 1e-12);
    // The depth and the turn: the map's local area stretch and rotation, its Jacobian by
    // central differences.
    const double h = 1e-6;
    Eigen::Matrix2d J;
    J.col(0) = (SeenRay(lens, x + h, y) - SeenRay(lens, x - h, y)) / (2 * h);
    J.col(1) = (SeenRay(lens, x, y + h) - SeenRay(lens, x, y - h)) / (2 * h);
    EXPECT_NEAR(T.t.z(), 900.0 / std::sqrt(J.determinant()), 1e-6) << x << ", " << y;
    const double turn = 0.5 * (J(1, 0) - J(0, 1));
    EXPECT_GT(std::abs(turn), 1e-3) << "the prism turns the image";
    const Eigen::AngleAxisd seen_turn(T.R * R.transpose());
    EXPECT_NEAR(seen_turn.angle(), std::abs(turn), 1e-8);
    EXPECT_NEAR(std::abs(seen_turn.axis().dot(T.t.normalized())), 1.0, 1e-8) << "about the ray";
  }
}

TEST(LensDistortion, WithK1AloneIsTheLibrarysRadialFormToFirstOrder) {
  // camera_intrinsics' radial term: x' = x (1 + k r^2), Z' = Z (1 - 2 k r^2), to first order.
  ConcealedPhysics lens = Lens(1e-3);
  lens.lens_shape.setZero();
  lens.lens_beyond.setZero();
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

// The board's position where camera_intrinsics with `terms` at `params` puts it.
Eigen::Vector3d ByTheLibrary(const std::string& terms, const std::vector<double>& params,
                             const Pose& T) {
  const auto ur3 = testing::Plugins().CreateRobotModel(
      "serial_mdh", ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml")));
  const ConfigNode config = ConfigNode::LoadString(
      "{type: camera_intrinsics, cameras: [cam1], terms: " + terms + "}", "test");
  const auto effect = testing::Plugins().CreateEffect("camera_intrinsics", config, *ur3);
  EffectContext context;
  context.camera = "cam1";
  std::vector<double> values = {T.t.x(), T.t.y(), T.t.z()};
  values.insert(values.end(), T.R.data(), T.R.data() + 9);
  effect->Apply(context, params.data(), values.data());
  return Eigen::Vector3d(values[0], values[1], values[2]);
}

TEST(LensDistortion, GoesBeyondTheLibrarysLensFormByThePrism) {
  // Without the prism (and k3), the library's [radial, k2, tangential] to first order in m; with
  // the default's prism, off by first-order terms the library has no parameter for.
  const double m = 1e-4;
  ConcealedPhysics within = Lens(m);
  within.lens_beyond.setZero();
  const std::vector<double> k1_k2_p1_p2 = {m, -0.4 * m, 0.2 * m, -0.1 * m};
  for (const auto& [x, y] : {std::pair{0.3, 0.2}, {-0.45, 0.1}, {0.05, -0.35}}) {
    const Pose board = BoardAt(x, y, 1000.0);
    const Eigen::Vector3d library = ByTheLibrary("[radial, k2, tangential]", k1_k2_p1_p2, board);
    Pose seen = board;
    within.MeasureInCamera("cam1", &seen);
    EXPECT_LT((seen.t - library).norm(), 1000.0 * 10.0 * m * m) << x << ", " << y;
    Pose beyond = board;
    Lens(m).MeasureInCamera("cam1", &beyond);
    EXPECT_GT((beyond.t - library).norm(), 1000.0 * 0.005 * m) << x << ", " << y;
  }
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

// One joint turning about the horizontal y axis, a 400 mm link of 1 kg to the flange at angle q
// from the horizontal: its gravity torque goes as cos q. Gravity holds the play against the
// flank it pushes to wherever |cos q| is beyond the 15 % hold; nearer the vertical the joint
// lags behind its last move.
TEST(GravityBacklash, HeldByGravityBeyondTheFrictionAndByTheLastMoveWithin) {
  ConcealedPhysics play;
  play.kind = "gravity_backlash";
  play.robot = "arm";
  play.joint = 0;
  play.magnitude = 2e-3;
  play.link_masses_kg = {1.0};
  const double half = 1e-3;
  const std::vector<double> qs = {0.0, 3.0, M_PI / 2 + 0.05, M_PI / 2 - 0.05, M_PI / 2 + 0.02, 0.2};
  const std::vector<double> expected = {half, -half, half, half, -half, half};
  Recording recording;
  std::vector<SampleFacts> facts;
  for (double q : qs) {
    Sample s;
    s.robot = "arm";
    s.q = {q};
    recording.samples.push_back(s);
    SampleFacts f;
    f.q = {q};
    Pose axis;  // the joint's z along the world's y
    axis.R = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).matrix();
    Pose flange;
    flange.t = 400.0 * Eigen::Vector3d(std::cos(q), 0.0, std::sin(q));
    f.T_base_joint = {axis, flange};
    facts.push_back(f);
  }
  const auto actions = play.Actions(recording, facts, Eigen::Vector3d(0, 0, -9.81));
  ASSERT_EQ(actions.size(), qs.size());
  for (size_t i = 0; i < qs.size(); ++i) {
    ASSERT_EQ(actions[i].dq.size(), 1u);
    EXPECT_DOUBLE_EQ(actions[i].dq[0], expected[i]) << "pose " << i << ", q = " << qs[i];
  }
}

}  // namespace
}  // namespace cellmetry
