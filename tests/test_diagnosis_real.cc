// The physics finder on real recordings, by the tool itself (docs/real-data.md):
// - experiment A (a UR3, three RealSense cameras): the finder names the camera-side physics an
//   engineer found by hand -- the boards' printed size and every camera's principal point, judged
//   as the shift the three share and each one's own -- and, as a frame the stated level
//   determines, the world tag's tilt; its final fit holds out within 3.5 mm and puts the base
//   within 5 mm of the measured placement and 3 sigma. Each camera alone: within 3 sigma.
// - the Staubli TX90L against a laser tracker: joint 2, 3 and 5 compliance under the arm's own
//   weight, every value from the 40 calibration poses.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "cellmetry/cell/camera_left_out.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/import/importer.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

// Whether an accepted effect has this name, or belongs to this group.
bool Accepted(const DiagnosisResult& d, const std::string& name) {
  return std::any_of(d.accepted.begin(), d.accepted.end(),
                     [&](const AcceptedEffect& a) { return a.name == name || a.group == name; });
}

const FrameEstimate& Base(const DiagnosisResult& d) {
  for (const FrameEstimate& f : d.final_fit.frames) {
    if (f.name == "ur3.base") return f;
  }
  throw std::runtime_error("no ur3.base in the final fit");
}

// `configs/jobs/vsb_exp_a_diagnose.yaml` without the cameras in `unused`, as `cellmetry diagnose
// --without` runs it.
DiagnosisResult DiagnoseExpA(const std::set<std::string>& unused) {
  DiagnosisJob job =
      LoadDiagnosisJob(testing::Source("configs/jobs/vsb_exp_a_diagnose.yaml"), testing::Plugins());
  for (const std::string& camera : unused) job.workcell.problem.cameras[camera].use = false;
  job.workcell.problem.leave_one_camera_out = false;
  const Recording recording =
      WithoutCameras(ReadRecording(job.workcell.recording), UnusedCameras(job.workcell.problem));
  return testing::Diagnose(job, recording, "vsb_exp_a_diagnose.yaml");
}

const Eigen::Vector3d kPlacement(431.0, 555.0, -460.0);

TEST(DiagnosisOnRealData, NamesExperimentAsCameraSidePhysicsAndPlacesTheBase) {
  const DiagnosisResult d = DiagnoseExpA({});
  EXPECT_TRUE(Accepted(d, "target.scale_every_target")) << DiagnosisReport(d);
  EXPECT_TRUE(Accepted(d, "camera.principal_every_camera")) << DiagnosisReport(d);
  EXPECT_TRUE(Accepted(d, "world_frame")) << DiagnosisReport(d);
  EXPECT_LE(d.final.held_out_rms_mm, 3.5);
  const FrameEstimate& base = Base(d);
  EXPECT_LE((base.pose.t - kPlacement).norm(), 5.0) << base.pose.t.transpose();
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(base.pose.t[i] - kPlacement[i]), 3 * base.sigma_mm[i]) << "xyz"[i];
  }
}

TEST(DiagnosisOnRealData, ExperimentAsSingleCamerasPlaceTheBaseWithinThreeSigma) {
  for (const std::string kept : {"cam1", "cam2", "cam3"}) {
    std::set<std::string> unused = {"cam1", "cam2", "cam3"};
    unused.erase(kept);
    const FrameEstimate& base = Base(DiagnoseExpA(unused));
    for (int i = 0; i < 3; ++i) {
      EXPECT_LT(std::abs(base.pose.t[i] - kPlacement[i]), 3 * base.sigma_mm[i])
          << kept << " alone: base "
          << "xyz"[i] << " = " << base.pose.t[i] << " +- " << base.sigma_mm[i];
    }
  }
}

// Joints 2 and 3 are described as compliances, joint 5 as play its gravity torque holds against
// one flank (docs/real-data.md): each as its joint giving under gravity.
TEST(DiagnosisOnRealData, NamesTheTx90lsJointsGivingUnderItsOwnWeight) {
  const DiagnosisJob job = LoadDiagnosisJob(
      testing::Source("configs/jobs/staubli_tx90l_diagnose.yaml"), testing::Plugins(), false);
  const Recording calibration =
      ImportRecording(testing::Source("configs/import/astl_calibration.yaml"));
  const DiagnosisResult d = testing::Diagnose(job, calibration, "staubli_tx90l_diagnose.yaml");
  for (const char* joint :
       {"tx90l.gravity_load_j2", "tx90l.gravity_load_j3", "tx90l.gravity_load_j5"}) {
    EXPECT_TRUE(Accepted(d, joint)) << joint << "\n" << DiagnosisReport(d);
  }
  EXPECT_LT(d.final.held_out_rms_mm, 0.07);
  EXPECT_LT(d.final.held_out_rms_mm, 0.6 * d.geometric.held_out_rms_mm);
  // Far beyond what the 40 poses' own scatter could give, scored row by row on the same folds.
  EXPECT_TRUE(d.held_out_gain.paired);
  EXPECT_GT(d.held_out_gain.gain_mm, 3 * d.held_out_gain.standard_error_mm) << DiagnosisReport(d);
  // Joint 5, accepted last, moves what joints 2 and 3 absorbed: the report gives the values the
  // final model holds beside each as it was accepted.
  EXPECT_NE(DiagnosisReport(d).find("Fitted together in the final model"), std::string::npos);
}

}  // namespace
}  // namespace cellmetry
