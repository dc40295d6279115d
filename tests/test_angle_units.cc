// Angles read wrongly are found by what they do (angle_unit_check.h): the flange turns unlike
// the target between captures, and reading one file's angles otherwise makes them agree. A
// robot config whose twists and offsets are radians but say `angle: deg` is refused at that
// line, the recording left alone, and the same config as written passes; an import whose
// quaternion columns were mapped in the other order is refused at the mapping's order, one whose
// Euler angles were read in the other convention at the mapping's axes (rpy: its convention).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/job.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

// vsb_sim_b.yaml with its robot config replaced by `robot_yaml`, written to `dir`.
WorkcellJob SimBWithRobot(const std::string& dir, const std::string& robot_yaml) {
  testing::WriteText(dir + "/ur3.yaml", robot_yaml);
  std::string job = testing::ReadText(testing::Source("configs/jobs/vsb_sim_b.yaml"));
  job = testing::ReplaceOnce(job, "../robots/ur3_vsb2020.yaml", dir + "/ur3.yaml");
  job = testing::ReplaceOnce(job, "../../tests/data/vsb/sim_b",
                             testing::Source("tests/data/vsb/sim_b"));
  testing::WriteText(dir + "/job.yaml", job);
  return LoadWorkcellJob(dir + "/job.yaml", testing::Plugins());
}

TEST(AngleUnits, RobotConfigInRadiansDeclaredAsDegreesIsRefusedAtItsUnitsLine) {
  const std::string dir = testing::TempDirForThisTest("angle_units");
  const std::string ur3 = testing::ReadText(testing::Source("configs/robots/ur3_vsb2020.yaml"));
  const Recording recording = ReadRecording(testing::Source("tests/data/vsb/sim_b"));
  // As written: no complaint.
  EXPECT_NO_THROW(ValidateJobAgainstRecording(SimBWithRobot(dir, ur3), recording));
  const WorkcellJob job = SimBWithRobot(dir, testing::ReplaceOnce(ur3, "angle: rad", "angle: deg"));
  try {
    ValidateJobAgainstRecording(job, recording);
    FAIL() << "a robot config's radians read as degrees were fitted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.where().file, HasSubstr("ur3.yaml"));
    EXPECT_EQ(e.where().line, 6);
    EXPECT_THAT(e.message(), HasSubstr("13 % apart with the robot config's angles in deg, "
                                       "0.1 % read in rad"));
    EXPECT_THAT(e.hint(), HasSubstr("The robot config's angles look like radians: declare "
                                    "units: {angle: rad}"));
  }
}

// The tracker's quaternions are scalar first (Leica's Q0..Q3); a mapping that says xyzw reads
// them as other rotations. `run` on that import names the mapping's order line in the
// recording's copy of the mapping.
TEST(AngleUnits, QuaternionColumnsInTheOtherOrderAreRefusedAtTheMappingsOrder) {
  const std::string dir = testing::TempDirForThisTest("angle_units");
  std::string mapping = testing::ReadText(testing::Source("configs/import/astl_calibration.yaml"));
  mapping = testing::ReplaceOnce(mapping, "order: wxyz", "order: xyzw");
  for (const char* table : {"joints_deg.csv", "leica.csv"}) {
    mapping =
        testing::ReplaceOnce(mapping, std::string("../../tests/data/astl/calibration/") + table,
                             testing::Source("tests/data/astl/calibration/") + table);
  }
  testing::WriteText(dir + "/map.yaml", mapping);
  ASSERT_EQ(testing::RunCellmetry("import " + dir + "/map.yaml -o " + dir + "/rec").exit_code, 0);
  std::string job = testing::ReadText(testing::Source("configs/jobs/staubli_tx90l_nominal.yaml"));
  job = testing::ReplaceOnce(job, "../../results/astl_calibration", dir + "/rec");
  job = job.substr(0, job.find("validation:"));  // no held-out setup
  job = testing::ReplaceOnce(job, "../robots/staubli_tx90l.yaml",
                             testing::Source("configs/robots/staubli_tx90l.yaml"));
  testing::WriteText(dir + "/job.yaml", job);
  const testing::CommandResult refused =
      testing::RunCellmetry("run " + dir + "/job.yaml -o " + dir + "/out");
  testing::ExpectOneLineError(refused, "rec/import.yaml:31:47:",
                              "14 % apart with the quaternion's columns read as xyzw, 0.0 % "
                              "read as wxyz");
  EXPECT_THAT(refused.output, HasSubstr("say order: wxyz in the mapping and import it again"));
}

// VSB experiment A's spreadsheet excerpt writes the tool's rotation as intrinsic XYZ Euler angles
// in degrees. Declared extrinsic (the same angles turned about the fixed axes) or rpy (fixed
// axes x, y, z), `run` on the import names the tool's `axes:` or `convention:` in the
// recording's copy of the mapping; declared as written, the recording passes the check. The
// margin is smaller than a unit's (2.6 % against the 2 % threshold): the two conventions differ
// in a turn's size only through the middle angle.
TEST(AngleUnits, EulerAnglesReadInTheOtherConventionAreRefusedAtTheMappingsAxes) {
  const std::string dir = testing::TempDirForThisTest("angle_units");
  const std::string as_written = testing::ReplaceOnce(
      testing::ReadText(testing::Source("configs/import/vsb_exp_a_excerpt.yaml")),
      "table: vsb_exp_a_excerpt.csv",
      "table: " + testing::Source("configs/import/vsb_exp_a_excerpt.csv"));
  std::string job = testing::ReadText(testing::Source("configs/jobs/vsb_exp_a_excerpt.yaml"));
  job = job.substr(0, job.find("validation:"));  // no cross-validation
  job = testing::ReplaceOnce(job, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  // The tool's rotation declared as `declared`; the job on its import, written to `dir`.
  const auto import_as = [&](const std::string& name, const std::string& declared) {
    const std::string tool =
        "convention: euler, order: XYZ, axes: intrinsic,\n"
        "               columns: [tool";
    testing::WriteText(dir + "/" + name + ".yaml",
                       testing::ReplaceOnce(as_written, tool,
                                            declared + ",\n"
                                                       "               columns: [tool"));
    const std::string recording = dir + "/rec_" + name;
    EXPECT_EQ(
        testing::RunCellmetry("import " + dir + "/" + name + ".yaml -o " + recording).exit_code, 0);
    testing::WriteText(dir + "/job_" + name + ".yaml",
                       testing::ReplaceOnce(job, "recording: ../../results/vsb_exp_a_excerpt\n",
                                            "recording: " + recording + "\n"));
    return dir + "/job_" + name + ".yaml";
  };
  const std::string right = import_as("right", "convention: euler, order: XYZ, axes: intrinsic");
  EXPECT_NO_THROW(ValidateJobAgainstRecording(LoadWorkcellJob(right, testing::Plugins()),
                                              ReadRecording(dir + "/rec_right")));
  // Line 23 of the mapping, below the two lines the recording's copy begins with.
  const testing::CommandResult extrinsic = testing::RunCellmetry(
      "run " + import_as("extrinsic", "convention: euler, order: XYZ, axes: extrinsic") + " -o " +
      dir + "/out");
  testing::ExpectOneLineError(extrinsic, "rec_extrinsic/import.yaml:25:53:",
                              "2.6 % apart with the Euler angles read as XYZ extrinsic, 0.1 % "
                              "read as XYZ intrinsic");
  EXPECT_THAT(extrinsic.output,
              HasSubstr("say axes: intrinsic in the mapping and import it again"));
  const testing::CommandResult rpy =
      testing::RunCellmetry("run " + import_as("rpy", "convention: rpy") + " -o " + dir + "/out");
  testing::ExpectOneLineError(rpy, "rec_rpy/import.yaml:25:28:",
                              "with the angles read as rpy (fixed axes x, y, z), 0.1 % read as "
                              "Euler XYZ about turned axes");
  EXPECT_THAT(rpy.output, HasSubstr("say convention: euler, order: XYZ, axes: intrinsic"));
}

}  // namespace
}  // namespace cellmetry
