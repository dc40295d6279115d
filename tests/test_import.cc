// cellmetry import: the rotation conventions pinned to their definitions, the table readers,
// and one simulated truth written as tables in every convention, unit and dialect — each
// imported recording is the truth to 1e-9.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>
#include <tuple>

#include "cellmetry/basics/transform.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/import/data_table.h"
#include "cellmetry/import/date_time.h"
#include "cellmetry/import/importer.h"
#include "cellmetry/import/rotation_conventions.h"
#include "cellmetry/import/text_encoding.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;
using testing::ReplaceOnce;

const char* const kEulerOrders[] = {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX",
                                    "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"};

Eigen::Matrix3d RandomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

double AngleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a * b.transpose()).angle();
}

// ---------------------------------------------------------------- rotation conventions

TEST(RotationConventions, IntrinsicTurnsAboutTheTurnedAxesExtrinsicAboutTheFixedOnes) {
  const double quarter = M_PI / 2;
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
  // Fixed axes: y turns about x into z, and z stays z under the turn about the fixed z.
  EXPECT_TRUE((EulerToRotation({0, 1, 2}, false, {quarter, 0, quarter}) * y)
                  .isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  // Turned axes: R = Rx Ry Rz; y turns about z into -x, which the turn about x leaves alone.
  EXPECT_TRUE((EulerToRotation({0, 1, 2}, true, {quarter, 0, quarter}) * y)
                  .isApprox(-Eigen::Vector3d::UnitX(), 1e-12));
}

TEST(RotationConventions, RollPitchYawIsFixedXyzAndTurnedZyxReversed) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  for (int n = 0; n < 20; ++n) {
    const double rpy[3] = {angle(rng), angle(rng) / 2, angle(rng)};
    RotationConvention c;
    c.kind = RotationKind::kRollPitchYaw;
    std::string problem;
    const Eigen::Matrix3d R = ToRotation(c, rpy, &problem);
    EXPECT_TRUE(problem.empty());
    const Eigen::Matrix3d expected = (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
                                         .toRotationMatrix();
    EXPECT_LT(AngleBetween(R, expected), 1e-14);
    EXPECT_LT(AngleBetween(R, EulerToRotation({2, 1, 0}, true, {rpy[2], rpy[1], rpy[0]})), 1e-14);
  }
}

TEST(RotationConventions, QuaternionScalarFirstAndLastAreTheSameRotation) {
  const double c = std::cos(M_PI / 4), s = std::sin(M_PI / 4);
  RotationConvention wxyz, xyzw;
  wxyz.kind = xyzw.kind = RotationKind::kQuaternion;
  xyzw.scalar_first = false;
  const double first[4] = {c, s, 0, 0}, last[4] = {s, 0, 0, c}, negated[4] = {-c, -s, 0, 0};
  std::string problem;
  const Eigen::Matrix3d Rx = AxisRotation(0, M_PI / 2);
  EXPECT_LT(AngleBetween(ToRotation(wxyz, first, &problem), Rx), 1e-15);
  EXPECT_LT(AngleBetween(ToRotation(xyzw, last, &problem), Rx), 1e-15);
  EXPECT_LT(AngleBetween(ToRotation(wxyz, negated, &problem), Rx), 1e-15);
  EXPECT_TRUE(problem.empty());
}

TEST(RotationConventions, EveryEulerSequenceMatchesEigenAndRoundTrips) {
  std::mt19937 rng(11);
  for (const char* order : kEulerOrders) {
    const auto axes = ParseEulerOrder(order);
    ASSERT_TRUE(axes) << order;
    const bool proper = (*axes)[0] == (*axes)[2];
    for (bool intrinsic : {true, false}) {
      SCOPED_TRACE(std::string(order) + (intrinsic ? " intrinsic" : " extrinsic"));
      for (int n = 0; n < 200; ++n) {
        const Eigen::Matrix3d R = RandomRotation(rng);
        const Eigen::Vector3d a = RotationToEuler(*axes, intrinsic, R);
        EXPECT_LT(AngleBetween(EulerToRotation(*axes, intrinsic, a), R), 1e-12);
        if (proper) {
          EXPECT_GE(a[1], 0.0);
          EXPECT_LE(a[1], M_PI);
        } else {
          EXPECT_LE(std::abs(a[1]), M_PI / 2 + 1e-15);
        }
      }
      // Eigen's eulerAngles(i, j, k) are turned-axes angles: the same composition.
      const Eigen::Matrix3d R = RandomRotation(rng);
      const Eigen::Vector3d e = R.eulerAngles((*axes)[0], (*axes)[1], (*axes)[2]);
      EXPECT_LT(AngleBetween(EulerToRotation(*axes, true, e), R), 1e-12);
      // At gimbal lock only the sum of the outer angles is defined; the rotation still returns.
      const double middle = proper ? 0.0 : M_PI / 2;
      const Eigen::Matrix3d locked = EulerToRotation(*axes, intrinsic, {0.3, middle, -1.1});
      EXPECT_LT(
          AngleBetween(EulerToRotation(*axes, intrinsic, RotationToEuler(*axes, intrinsic, locked)),
                       locked),
          1e-12);
    }
  }
  EXPECT_FALSE(ParseEulerOrder("XXY"));
  EXPECT_FALSE(ParseEulerOrder("xyz"));
  EXPECT_FALSE(ParseEulerOrder("XY"));
}

TEST(RotationConventions, FromRotationInvertsToRotationInEveryConvention) {
  std::vector<RotationConvention> conventions(5);
  conventions[0].kind = RotationKind::kEuler;
  conventions[0].euler_axes = {2, 0, 2};
  conventions[0].intrinsic = false;
  conventions[1].kind = RotationKind::kRollPitchYaw;
  conventions[2].kind = RotationKind::kQuaternion;
  conventions[2].scalar_first = false;
  conventions[3].kind = RotationKind::kRotationVector;
  conventions[4].kind = RotationKind::kMatrix;
  std::mt19937 rng(5);
  for (const auto& c : conventions) {
    SCOPED_TRACE(c.Describe());
    for (int n = 0; n < 50; ++n) {
      const Eigen::Matrix3d R = RandomRotation(rng);
      const std::array<double, 9> values = FromRotation(c, R);
      std::string problem;
      EXPECT_LT(AngleBetween(ToRotation(c, values.data(), &problem), R), 1e-12);
      EXPECT_TRUE(problem.empty()) << problem;
    }
  }
}

TEST(RotationConventions, NamesWhatIsNotARotation) {
  RotationConvention quaternion, matrix;
  quaternion.kind = RotationKind::kQuaternion;
  matrix.kind = RotationKind::kMatrix;
  std::string problem;
  const double long_q[4] = {1.02, 0, 0, 0};
  ToRotation(quaternion, long_q, &problem);
  EXPECT_THAT(problem, HasSubstr("length is 1.02, not 1"));
  const double rounded_q[4] = {1.0004, 0, 0, 0};  // within the default 1e-3
  ToRotation(quaternion, rounded_q, &problem);
  EXPECT_TRUE(problem.empty());
  const double sheared[9] = {1, 0.01, 0, 0, 1, 0, 0, 0, 1};
  ToRotation(matrix, sheared, &problem);
  EXPECT_THAT(problem, HasSubstr("not orthonormal"));
  const double mirrored[9] = {1, 0, 0, 0, 1, 0, 0, 0, -1};
  ToRotation(matrix, mirrored, &problem);
  EXPECT_THAT(problem, HasSubstr("a mirrored frame"));
}

// ---------------------------------------------------------------- table readers

TEST(DataTable, CsvWithByteOrderMarkQuotesSemicolonsAndDecimalCommas) {
  const std::string dir = testing::TempDirForThisTest("import");
  testing::WriteText(dir + "/t.csv",
                     "\xEF\xBB\xBF"
                     "capture;\"name; with separator\";value\r\n"
                     "\r\n"
                     "1;\"say \"\"hi\"\"\";-1,5\r\n"
                     "2;\"two\nlines\";+2e-3\r\n"
                     "3;plain\r\n");
  const DataTable t = ReadCsvTable(dir + "/t.csv", {});
  ASSERT_EQ(t.columns(), (std::vector<std::string>{"capture", "name; with separator", "value"}));
  ASSERT_EQ(t.num_rows(), 3u);
  EXPECT_EQ(t.Cell(0, 1), "say \"hi\"");
  EXPECT_EQ(t.Cell(1, 1), "two\nlines");
  EXPECT_TRUE(t.IsEmpty(2, 2));
  // Decimal commas are read only when the mapping says so.
  const auto error = testing::CatchInputError([&] { t.Number(0, 2); });
  EXPECT_EQ(FormatLocation(error.where()), dir + "/t.csv:3:3: ");
  EXPECT_THAT(error.hint(), HasSubstr("decimal: \",\""));
  const DataTable comma = ReadCsvTable(dir + "/t.csv", {0, ','});
  EXPECT_EQ(comma.Number(0, 2), -1.5);
  EXPECT_EQ(comma.Number(1, 2), 2e-3);
  EXPECT_EQ(FormatLocation(comma.Where(2, 0)), dir + "/t.csv:6:1: ");  // after the quoted break
}

TEST(DataTable, JsonLinesFlattenNestedObjectsAndArrays) {
  const std::string dir = testing::TempDirForThisTest("import");
  testing::WriteText(
      dir + "/t.jsonl",
      "{\"id\": 1, \"pose\": {\"t\": [0.1, 0.2, 0.30000000000000004]}, \"cam\": \"c1\"}\n"
      "\n"
      "{\"id\": 2, \"pose\": {\"t\": [1, 2, 3]}, \"note\": null}\n");
  const DataTable t = ReadJsonLinesTable(dir + "/t.jsonl");
  EXPECT_EQ(t.columns(),
            (std::vector<std::string>{"id", "pose.t[0]", "pose.t[1]", "pose.t[2]", "cam", "note"}));
  EXPECT_EQ(t.Number(0, 3), 0.30000000000000004);  // every digit kept
  EXPECT_EQ(t.Cell(0, 4), "c1");
  EXPECT_TRUE(t.IsEmpty(1, 4));
  EXPECT_EQ(FormatLocation(t.Where(1, 1)), dir + "/t.jsonl:3:19: ");
}

TEST(DataTable, ParseDecimalIsStrict) {
  std::string problem;
  EXPECT_EQ(ParseDecimal(" -12.5e-1 ", '.', &problem), -1.25);
  EXPECT_FALSE(ParseDecimal("1.5x", '.', &problem));
  EXPECT_THAT(problem, HasSubstr("is not a number"));
  EXPECT_FALSE(ParseDecimal("nan", '.', &problem));
  EXPECT_FALSE(ParseDecimal("1.234,5", ',', &problem));
  EXPECT_THAT(problem, HasSubstr("decimal mark is ','"));
  EXPECT_EQ(ParseDecimal("1234,5", ',', &problem), 1234.5);
}

TEST(DateTime, ReadsAnInstrumentsClockToTheMillisecond) {
  std::string problem;
  // Leica's export: a leading apostrophe (a spreadsheet's "text" mark), day first, a fraction.
  const auto t0 = ParseDateTime("'20.10.2022 16:57:12.092", "'%d.%m.%Y %H:%M:%S", &problem);
  ASSERT_TRUE(t0) << problem;
  EXPECT_EQ(t0->whole_s, 1666285032);  // date -u -d '2022-10-20 16:57:12' +%s
  EXPECT_NEAR(t0->fraction_s, 0.092, 1e-15);
  // Across midnight, a month end and a leap day; ISO 8601 with a decimal comma.
  const auto t1 = ParseDateTime(" 2024-03-01T00:00:01,5 ", "%Y-%m-%dT%H:%M:%S", &problem);
  const auto t2 = ParseDateTime("2024-02-28T23:59:59", "%Y-%m-%dT%H:%M:%S", &problem);
  ASSERT_TRUE(t1 && t2) << problem;
  EXPECT_EQ(t1->SecondsSince(*t2), 86400.0 + 2.5);  // 29 February lies between them
  EXPECT_EQ(ParseDateTime("1970-01-01 00:00", "%Y-%m-%d %H:%M", &problem)->whole_s, 0);
}

TEST(DateTime, NamesWhatDoesNotRead) {
  std::string problem;
  const std::string iso = "%Y-%m-%d %H:%M:%S";
  EXPECT_FALSE(ParseDateTime("2022-10-20 16:57", iso, &problem));
  EXPECT_THAT(problem, HasSubstr("expected ':' at character 17"));
  EXPECT_FALSE(ParseDateTime("2022-02-29 10:00:00", iso, &problem));
  EXPECT_THAT(problem, HasSubstr("is not a date and time"));
  EXPECT_FALSE(ParseDateTime("2022-10-20 16:57:12 CET", iso, &problem));
  EXPECT_THAT(problem, HasSubstr("' CET' is left over"));
  EXPECT_FALSE(ParseDateTime("20.10.2022 16:57:12", iso, &problem));
  EXPECT_THAT(problem, HasSubstr("expected '-' at character 3"));
  EXPECT_THAT(DateTimeFormatProblem("%H:%M:%S").value_or(""), HasSubstr("no %Y"));
  EXPECT_THAT(DateTimeFormatProblem("%Y-%m-%d %H:%M %p").value_or(""), HasSubstr("%p"));
  EXPECT_THAT(DateTimeFormatProblem("%Y-%m-%d %H:%M:%M").value_or(""), HasSubstr("%M twice"));
  EXPECT_FALSE(DateTimeFormatProblem("%d/%m/%Y %H:%M 100%%"));
}

// ---------------------------------------------------------------- two tables, 8-bit, uncertainty

// A robot log and a tracker log as separate files, and a mapping that joins them. Both tables
// have a column `time`; the tracker's positions are in mm with per-axis U(95).
class TwoTables : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::TempDirForThisTest("import"); }

  void WriteRobot(const std::string& time_column_and_rows) {
    testing::WriteText(dir_ + "/robot.csv", "time,q1,q2\n" + time_column_and_rows);
  }
  void WriteTracker(const std::string& rows) {
    testing::WriteText(dir_ + "/tracker.csv", "time,x,y,z,ux,uy,uz\n" + rows);
  }
  // The mapping with `join` (and `extra` keys at its end).
  std::string WriteMapping(const std::string& join, const std::string& extra = "") {
    const std::string path = dir_ + "/map.yaml";
    testing::WriteText(path,
                       "mapping: cellmetry-import/1\n"
                       "tables: {robot: robot.csv, tracker: tracker.csv}\n"
                       "join: " +
                           join +
                           "\n"
                           "units: {length: mm, angle: rad}\n"
                           "robot: {name: arm, joints: [q1, q2]}\n"
                           "targets: {probe: {on: arm}}\n"
                           "observations:\n"
                           "  - camera: tracker\n"
                           "    target: probe\n"
                           "    position: [x, y, z]\n" +
                           extra);
    return path;
  }

  std::string dir_;
};

TEST_F(TwoTables, JoinedByRowReadRowIOfEachAndNameACollidingColumnByItsTable) {
  WriteRobot("10,0.1,0.2\n11,0.3,0.4\n12,0.5,0.6\n");
  WriteTracker("1000,1,2,3,0.1,0.1,0.1\n1001,4,5,6,0.1,0.1,0.1\n1002,7,8,9,0.1,0.1,0.1\n");
  const Recording r = ImportRecording(
      WriteMapping("{by: row}", "facts: {time: {table: tracker, column: time, unit: ms}}\n"));
  ASSERT_EQ(r.samples.size(), 3u);
  ASSERT_EQ(r.observations.size(), 3u);
  EXPECT_EQ(r.samples[2].q, (std::vector<double>{0.5, 0.6}));
  EXPECT_EQ(r.observations[2].position_mm, Eigen::Vector3d(7, 8, 9));
  EXPECT_DOUBLE_EQ(*r.samples[1].time_s, 1.001);  // the tracker's time, not the robot's
  EXPECT_THAT(r.description, HasSubstr("robot.csv + tracker.csv"));
  // `tracker.time` names the same column; `time` alone could be either, and is refused.
  const Recording prefixed =
      ImportRecording(WriteMapping("{by: row}", "facts: {time: tracker.time}\n"));
  EXPECT_DOUBLE_EQ(*prefixed.samples[0].time_s, 1000.0);
  const auto e = testing::CatchInputError(
      [&] { ImportRecording(WriteMapping("{by: row}", "facts: {time: time}\n")); });
  EXPECT_EQ(FormatLocation(e.where()), dir_ + "/map.yaml:11:15: ");
  EXPECT_THAT(e.message(), HasSubstr("could be 'time' of robot.csv or 'time' of tracker.csv"));
  EXPECT_THAT(e.hint(), HasSubstr("Say which: robot.time or {table: robot, column: ...}"));
}

TEST_F(TwoTables, JoinedByRowTablesOfDifferentLengthsAreRefusedAtTheFirstRowWithoutPartner) {
  WriteRobot("10,0.1,0.2\n11,0.3,0.4\n");
  WriteTracker("1000,1,2,3,0.1,0.1,0.1\n1001,4,5,6,0.1,0.1,0.1\n1002,7,8,9,0.1,0.1,0.1\n");
  const auto e = testing::CatchInputError([&] { ImportRecording(WriteMapping("{by: row}")); });
  EXPECT_EQ(FormatLocation(e.where()), dir_ + "/tracker.csv:4:1: ");
  EXPECT_EQ(e.message(), "tracker.csv has 3 data rows but " + dir_ +
                             "/robot.csv has 2: this row has no partner");
  EXPECT_THAT(e.hint(), HasSubstr("join them by time"));
}

TEST_F(TwoTables, JoinedByTimeEachRowTakesTheNearestWithinTheTolerance) {
  WriteRobot("0,0.1,0.2\n1,0.3,0.4\n2,0.5,0.6\n");
  // Out of order, in ms, each a few ms off the robot's clock.
  WriteTracker("1996,7,8,9,0.1,0.1,0.1\n4,1,2,3,0.1,0.1,0.1\n1003,4,5,6,0.1,0.1,0.1\n");
  const Recording r = ImportRecording(WriteMapping(
      "{by: time, columns: {robot: time, tracker: {column: time, unit: ms}}, tolerance_s: 0.005}",
      "facts: {time: robot.time}\n"));
  ASSERT_EQ(r.observations.size(), 3u);
  EXPECT_EQ(r.observations[0].position_mm, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(r.observations[1].position_mm, Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(r.observations[2].position_mm, Eigen::Vector3d(7, 8, 9));
  EXPECT_EQ(*r.samples[2].time_s, 2.0);
}

TEST_F(TwoTables, JoinedByTimeARowWithoutPartnerIsRefusedAtItsTimeCell) {
  WriteRobot("0,0.1,0.2\n1,0.3,0.4\n2,0.5,0.6\n");
  WriteTracker("0,1,2,3,0.1,0.1,0.1\n1500,4,5,6,0.1,0.1,0.1\n2000,7,8,9,0.1,0.1,0.1\n");
  const std::string join =
      "{by: time, columns: {robot: time, tracker: {column: time, unit: ms}}, tolerance_s: 0.01}";
  auto e = testing::CatchInputError([&] { ImportRecording(WriteMapping(join)); });
  EXPECT_EQ(FormatLocation(e.where()), dir_ + "/robot.csv:3:1: ");
  EXPECT_THAT(e.message(), HasSubstr("column 'time' of data row 2: no row of " + dir_ +
                                     "/tracker.csv within 0.01 s of 1 s (the nearest, data row "
                                     "2 (line 3), is 0.5 s away)"));
  // A tracker row no robot row takes: refused at the tracker's cell.
  WriteRobot("0,0.1,0.2\n2,0.5,0.6\n");
  e = testing::CatchInputError([&] { ImportRecording(WriteMapping(join)); });
  EXPECT_EQ(FormatLocation(e.where()), dir_ + "/tracker.csv:3:1: ");
  EXPECT_THAT(e.message(), HasSubstr("took this row as its partner"));
}

TEST_F(TwoTables, ADateTimeColumnIsSecondsSinceTheEarliestAndABadCellIsNamed) {
  WriteRobot("10,0.1,0.2\n11,0.3,0.4\n12,0.5,0.6\n");
  WriteTracker(
      "2022-10-20 23:59:58.5,1,2,3,0,0,0\n2022-10-21 00:00:01,4,5,6,0,0,0\n"
      "2022-10-20 23:59:58,7,8,9,0,0,0\n");
  const std::string time =
      "facts: {time: {table: tracker, column: time, format: \"%Y-%m-%d %H:%M:%S\"}}\n";
  const Recording r = ImportRecording(WriteMapping("{by: row}", time));
  ASSERT_EQ(r.samples.size(), 3u);
  EXPECT_DOUBLE_EQ(*r.samples[0].time_s, 0.5);  // the last row is the earliest
  EXPECT_DOUBLE_EQ(*r.samples[1].time_s, 3.0);  // across midnight
  EXPECT_DOUBLE_EQ(*r.samples[2].time_s, 0.0);

  WriteTracker(
      "2022-10-20 23:59:58,1,2,3,0,0,0\n20.10.2022 23:59:59,4,5,6,0,0,0\n"
      "2022-10-20 23:59:59,7,8,9,0,0,0\n");
  const auto bad =
      testing::CatchInputError([&] { ImportRecording(WriteMapping("{by: row}", time)); });
  EXPECT_EQ(FormatLocation(bad.where()), dir_ + "/tracker.csv:3:1: ");
  EXPECT_THAT(bad.message(), HasSubstr("column 'time' of data row 2: '20.10.2022 23:59:59' does "
                                       "not read as %Y-%m-%d %H:%M:%S"));
  EXPECT_THAT(bad.hint(), HasSubstr("write the format its column has"));

  const auto unit = testing::CatchInputError([&] {
    ImportRecording(WriteMapping(
        "{by: row}",
        "facts: {time: {column: tracker.time, format: \"%Y-%m-%d %H:%M\", unit: s}}\n"));
  });
  EXPECT_THAT(unit.message(), HasSubstr("it has no unit"));
  const auto format = testing::CatchInputError([&] {
    ImportRecording(
        WriteMapping("{by: row}", "facts: {time: {column: tracker.time, format: \"%H:%M:%S\"}}\n"));
  });
  EXPECT_THAT(format.message(), HasSubstr("cannot read a date-time: it has no %Y"));
}

TEST(EightBitText, Latin1IsReadAsUtf8AndAColumnIsNamedWithItsDegreeSign) {
  const std::string dir = testing::TempDirForThisTest("import");
  // Windows-1252: 0xB0 the degree sign, 0xB5 micro, 0x80 the euro sign.
  testing::WriteText(dir + "/log.csv",
                     "Temperature  [\xB0"
                     "C],Image RMS  [\xB5"
                     "m],note\r\n"
                     "22.8,0.22,\x80"
                     "5\r\n");
  CsvDialect latin1;
  latin1.encoding = TextEncoding::kWindows1252;
  const DataTable t = ReadCsvTable(dir + "/log.csv", latin1);
  EXPECT_EQ(t.columns(),
            (std::vector<std::string>{"Temperature  [°C]", "Image RMS  [µm]", "note"}));
  EXPECT_EQ(t.Cell(0, 2), "€5");
  // Without the encoding: refused at the field, naming the byte and what to add.
  const auto e = testing::CatchInputError([&] { ReadCsvTable(dir + "/log.csv", {}); });
  EXPECT_EQ(FormatLocation(e.where()), dir + "/log.csv:1:1: ");
  EXPECT_EQ(e.message(),
            "the byte 0xB0 in field 1 (after 'Temperature  [') is not UTF-8: the "
            "table is in an 8-bit encoding");
  EXPECT_THAT(e.hint(), HasSubstr("encoding: latin1"));
}

TEST_F(TwoTables, ATemperatureInDegreesIsReadFromTheSecondTableInLatin1) {
  WriteRobot("10,0.1,0.2\n11,0.3,0.4\n");
  testing::WriteText(dir_ + "/tracker.csv",
                     "X  [mm],Y  [mm],Z  [mm],Temperature  [\xB0"
                     "C]\r\n"
                     "1,2,3,22.8\r\n4,5,6,23.1\r\n");
  std::string mapping = testing::ReadText(WriteMapping(
      "{by: row}", "facts: {temperature: {column: \"Temperature  [°C]\", unit: C}}\n"));
  mapping = ReplaceOnce(mapping, "tracker: tracker.csv",
                        "tracker: {path: tracker.csv, encoding: windows-1252}");
  // Exactly as the header has it, and (a unique match) with its spaces collapsed.
  mapping = ReplaceOnce(mapping, "[x, y, z]", "[\"X  [mm]\", \"tracker.Y  [mm]\", \"Z [mm]\"]");
  testing::WriteText(dir_ + "/map.yaml", mapping);
  const Recording r = ImportRecording(dir_ + "/map.yaml");
  EXPECT_EQ(*r.samples[1].temperature_c, 23.1);
  EXPECT_EQ(r.observations[1].position_mm, Eigen::Vector3d(4, 5, 6));
  // Without the encoding the import stops at the header's byte.
  testing::WriteText(dir_ + "/map.yaml", ReplaceOnce(mapping, ", encoding: windows-1252", ""));
  const auto e = testing::CatchInputError([&] { ImportRecording(dir_ + "/map.yaml"); });
  EXPECT_EQ(FormatLocation(e.where()), dir_ + "/tracker.csv:1:4: ");
  EXPECT_THAT(e.message(), HasSubstr("the byte 0xB0 in field 4"));
}

TEST_F(TwoTables, UncertaintyColumnsGiveADiagonalCovarianceOfSigmaSquared) {
  WriteRobot("10,0.1,0.2\n11,0.3,0.4\n");
  WriteTracker("1000,1,2,3,0.003,0.001,0.0196\n1001,4,5,6,0.01,0.02,0.03\n");
  const std::string dir = dir_;
  const Recording r = ImportRecording(
      WriteMapping("{by: row}",
                   "    position_uncertainty: {columns: [ux, uy, uz], level: 0.95}\n"
                   "    rotation: {convention: rotation_vector, columns: [q1, q2, q1]}\n"
                   "    rotation_sigma: [0.01, 0.02, 0.03]\n"));
  ASSERT_TRUE(r.observations[0].covariance_mm2);
  // U(95) = 1.96 sigma (GUM G.1.3): sigma = U / 1.96.
  const Eigen::Vector3d u(0.003, 0.001, 0.0196);
  const Eigen::Matrix3d expected = (u / 1.96).cwiseAbs2().asDiagonal();
  EXPECT_TRUE(r.observations[0].covariance_mm2->isApprox(expected, 1e-12))
      << *r.observations[0].covariance_mm2;
  EXPECT_EQ((*r.observations[0].covariance_mm2)(0, 1), 0.0);
  EXPECT_TRUE(r.observations[1].rotation_covariance_rad2->isApprox(
      Eigen::Vector3d(1e-4, 4e-4, 9e-4).asDiagonal().toDenseMatrix(), 1e-12));
  // level: sigma takes the cells as standard deviations; they reach the recording's columns.
  const Recording sigma = ImportRecording(WriteMapping(
      "{by: row}", "    position_uncertainty: {columns: [ux, uy, uz], level: sigma}\n"));
  EXPECT_NEAR((*sigma.observations[1].covariance_mm2)(2, 2), 0.03 * 0.03, 1e-15);
  WriteRecording(sigma, dir + "/recording");
  EXPECT_THAT(testing::ReadText(dir + "/recording/observations.csv"), HasSubstr(",cov_xx,"));
  EXPECT_NEAR((*ReadRecording(dir + "/recording").observations[1].covariance_mm2)(1, 1),
              0.02 * 0.02, 1e-15);
}

TEST_F(TwoTables, AnUncertaintyThatIsNotAPositiveNumberIsRefusedAtItsCell) {
  const std::string mapping =
      WriteMapping("{by: row}", "    position_uncertainty: {columns: [ux, uy, uz], level: 0.95}\n");
  WriteRobot("10,0.1,0.2\n11,0.3,0.4\n");
  for (const auto& [cell, message] : std::vector<std::pair<std::string, std::string>>{
           {"abc", "column 'uy' of data row 2: 'abc' is not a number"},
           {"-0.01", "column 'uy' of data row 2: an uncertainty of -0.01 is not positive"},
           {"0", "column 'uy' of data row 2: an uncertainty of 0 is not positive"}}) {
    SCOPED_TRACE(cell);
    WriteTracker("1000,1,2,3,0.1,0.1,0.1\n1001,4,5,6,0.1," + cell + ",0.1\n");
    const auto e = testing::CatchInputError([&] { ImportRecording(mapping); });
    EXPECT_EQ(FormatLocation(e.where()), dir_ + "/tracker.csv:3:6: ");
    EXPECT_EQ(e.message(), message);
    if (cell == "0") {
      EXPECT_THAT(e.hint(), HasSubstr("minimum: 0.0005"));
    }
  }
  // An instrument that rounds its uncertainties: a stated minimum is read for a 0 (and for
  // anything below it); a negative cell is still refused.
  const Recording r = ImportRecording(WriteMapping(
      "{by: row}",
      "    position_uncertainty: {columns: [ux, uy, uz], level: 0.95, minimum: 0.0005}\n"));
  EXPECT_DOUBLE_EQ((*r.observations[1].covariance_mm2)(1, 1), std::pow(0.0005 / 1.96, 2));
  EXPECT_DOUBLE_EQ((*r.observations[1].covariance_mm2)(0, 0), std::pow(0.1 / 1.96, 2));
}

// The ASTL dataset as published (configs/import/astl_calibration.yaml): two files joined by
// row, the tracker's header in Windows-1252, U(95) per axis, the temperature in °C.
TEST(BundledExample, AstlCalibrationImportsAsPublished) {
  const std::string mapping = testing::Source("configs/import/astl_calibration.yaml");
  const Recording r = ImportRecording(mapping);
  ASSERT_EQ(r.samples.size(), 40u);
  ASSERT_EQ(r.observations.size(), 40u);
  EXPECT_EQ(r.cameras, std::vector<std::string>{"tracker"});
  EXPECT_EQ(r.targets.at("tmac"), "tx90l");
  EXPECT_EQ(r.samples[39].pose, 39);  // each sample its own pose
  // Row 1: joints -10, 0, 90, 20, -20, -50 deg; X, Y, Z 754, -3193.366, 303.745 mm; U(95) X, Y,
  // Z 0.003, 0.001, 0.003 mm; Q0..Q3 0.227782, -0.114534, 0.572354, 0.779364; 22.8 °C.
  const double deg = M_PI / 180;
  EXPECT_EQ(r.samples[0].q,
            (std::vector<double>{-10 * deg, 0 * deg, 90 * deg, 20 * deg, -20 * deg, -50 * deg}));
  const Observation& o = r.observations[0];
  EXPECT_EQ(o.camera, "tracker");
  EXPECT_EQ(o.target, "tmac");
  EXPECT_EQ(o.position_mm, Eigen::Vector3d(754, -3193.366, 303.745));
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(0.227782, -0.114534, 0.572354, 0.779364).normalized();
  EXPECT_LT(AngleBetween(RotationFromRvec(o.rvec->data()), q.toRotationMatrix()), 1e-12);
  ASSERT_TRUE(o.covariance_mm2);
  const Eigen::Matrix3d cov =
      (Eigen::Vector3d(0.003, 0.001, 0.003) / 1.96).cwiseAbs2().asDiagonal();
  EXPECT_TRUE(o.covariance_mm2->isApprox(cov, 1e-12)) << *o.covariance_mm2;
  EXPECT_FALSE(o.rotation_covariance_rad2);
  EXPECT_EQ(*r.samples[0].temperature_c, 22.8);
  // The tracker's clock: '11.10.2022 15:06:48.043 for row 1, 15:06:55.562 for row 2.
  ASSERT_TRUE(r.samples[0].time_s && r.samples[1].time_s);
  EXPECT_EQ(*r.samples[0].time_s, 0.0);
  EXPECT_NEAR(*r.samples[1].time_s, 7.519, 1e-12);
}

// ---------------------------------------------------------------- one truth, every convention

// How one table writes the truth.
struct Variant {
  std::string name;
  std::string rotation;   // euler ORDER, rpy, wxyz, xyzw, rotvec, matrix, matrix_prefix,
                          // transform, transform12, position
  bool intrinsic = true;  // euler
  bool metres = false;
  bool degrees = false;
  std::string dialect = "csv";  // csv | csv_semicolon (decimal comma, BOM) | jsonl
  bool wide = false;            // one row per sample, a column group per (camera, target)
  bool camera_in_target = false;
  bool poses_by_joints = false;
  bool fact_units = false;  // facts in ms, K and g
};

void PrintTo(const Variant& v, std::ostream* out) { *out << v.name; }

std::string Num(double value, const Variant& v) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", value);
  std::string s = text;
  if (v.dialect == "csv_semicolon") std::replace(s.begin(), s.end(), '.', ',');
  return s;
}

// The rotation columns' names and the mapping's rotation entry (prefix: the column group).
struct RotationColumns {
  std::vector<std::string> names;
  std::string mapping;  // "rotation: {...}" or "transform: {...}" or ""
};

std::string List(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& n : names) text += (text.empty() ? "" : ", ") + ("\"" + n + "\"");
  return "[" + text + "]";
}

RotationColumns RotationColumnsOf(const Variant& v, const std::string& prefix) {
  RotationColumns c;
  auto numbered = [&](int n) {
    for (int i = 0; i < n; ++i) c.names.push_back(prefix + "r" + std::to_string(i));
  };
  const std::string r = v.rotation;
  if (r == "position") return c;
  if (r == "rpy") {
    numbered(3);
    c.mapping = "rotation: {convention: rpy, columns: " + List(c.names) + "}";
  } else if (r == "wxyz" || r == "xyzw") {
    numbered(4);
    c.mapping = "rotation: {convention: quaternion, order: " + r + ", columns: " + List(c.names) +
                ", tolerance: 1e-9}";
  } else if (r == "rotvec") {
    numbered(3);
    c.mapping = "rotation: {convention: rotation_vector, columns: " + List(c.names) + "}";
  } else if (r == "matrix") {
    numbered(9);
    c.mapping = "rotation: {convention: matrix, columns: " + List(c.names) + ", tolerance: 1e-9}";
  } else if (r == "matrix_prefix") {
    for (int i = 1; i <= 3; ++i) {
      for (int k = 1; k <= 3; ++k) c.names.push_back(prefix + "R" + std::to_string(10 * i + k));
    }
    c.mapping = "rotation: {convention: matrix, prefix: \"" + prefix + "R\", tolerance: 1e-9}";
  } else if (r == "transform") {  // the whole 4x4 by prefix, bottom row included
    for (int i = 1; i <= 4; ++i) {
      for (int k = 1; k <= 4; ++k) c.names.push_back(prefix + "T" + std::to_string(10 * i + k));
    }
    c.mapping = "transform: {prefix: \"" + prefix + "T\", tolerance: 1e-9}";
  } else if (r == "transform12") {  // its top three rows, by name
    for (int i = 0; i < 12; ++i) c.names.push_back(prefix + "m" + std::to_string(i));
    c.mapping = "transform: {columns: " + List(c.names) + ", tolerance: 1e-9}";
  } else {  // an Euler order
    numbered(3);
    c.mapping = "rotation: {convention: euler, order: " + r +
                ", axes: " + (v.intrinsic ? "intrinsic" : "extrinsic") +
                ", columns: " + List(c.names) + "}";
  }
  return c;
}

// The truth's pose as the variant's table writes it (Eigen's own decompositions, not the
// importer's: the table is written independently of the code that reads it).
std::vector<double> PoseCells(const Observation& o, const Variant& v, bool negate_quaternion) {
  Eigen::Matrix3d R = RotationFromRvec(o.rvec->data());
  Eigen::Vector3d t = o.position_mm;
  if (v.camera_in_target) {
    R.transposeInPlace();
    t = -(R * t);
  }
  const double length = v.metres ? 1e-3 : 1.0;
  const double angle = v.degrees ? 180.0 / M_PI : 1.0;
  std::vector<double> cells;
  const std::string r = v.rotation;
  if (r == "transform" || r == "transform12") {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) cells.push_back(R(i, k));
      cells.push_back(t[i] * length);
    }
    if (r == "transform") cells.insert(cells.end(), {0, 0, 0, 1});
    return cells;
  }
  for (int i = 0; i < 3; ++i) cells.push_back(t[i] * length);
  if (r == "position") return cells;
  if (r == "rpy") {
    const Eigen::Vector3d e = R.eulerAngles(2, 1, 0);  // yaw, pitch, roll
    for (double a : {e[2], e[1], e[0]}) cells.push_back(a * angle);
  } else if (r == "wxyz" || r == "xyzw") {
    Eigen::Quaterniond q(R);
    if (negate_quaternion) q.coeffs() = -q.coeffs();  // the same rotation
    const std::vector<double> values = r == "wxyz"
                                           ? std::vector<double>{q.w(), q.x(), q.y(), q.z()}
                                           : std::vector<double>{q.x(), q.y(), q.z(), q.w()};
    cells.insert(cells.end(), values.begin(), values.end());
  } else if (r == "rotvec") {
    const Eigen::AngleAxisd aa(R);
    for (int i = 0; i < 3; ++i) cells.push_back(aa.axis()[i] * aa.angle() * angle);
  } else if (r == "matrix" || r == "matrix_prefix") {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) cells.push_back(R(i, k));
    }
  } else {
    const auto axes = *ParseEulerOrder(r);
    // Fixed axes (i, j, k) by (a, b, c) are turned axes (k, j, i) by (c, b, a).
    Eigen::Vector3d e = v.intrinsic ? R.eulerAngles(axes[0], axes[1], axes[2])
                                    : R.eulerAngles(axes[2], axes[1], axes[0]);
    if (!v.intrinsic) e = Eigen::Vector3d(e[2], e[1], e[0]);
    for (int i = 0; i < 3; ++i) cells.push_back(e[i] * angle);
  }
  return cells;
}

// One table row: named cells in order.
using Row = std::vector<std::pair<std::string, std::string>>;

std::string WriteTable(const std::vector<Row>& rows, const Variant& v) {
  std::string text;
  if (v.dialect == "jsonl") {
    for (const auto& row : rows) {
      // Columns named a[i] are written as arrays; a.b as nested objects, one level.
      std::string line = "{";
      std::string open_array, open_object;
      bool first = true;
      auto close = [&] {
        if (!open_array.empty()) line += "]";
        open_array.clear();
      };
      for (const auto& [name, value] : row) {
        std::string key = name, member;
        const size_t dot = name.find('.');
        std::string object = dot == std::string::npos ? "" : name.substr(0, dot);
        if (!object.empty()) key = name.substr(dot + 1);
        const size_t bracket = key.find('[');
        const std::string array = bracket == std::string::npos ? "" : key.substr(0, bracket);
        const bool quoted = value.empty() || !(std::isdigit(value[0]) || value[0] == '-');
        const std::string json_value = value.empty() ? "null"
                                       : quoted      ? "\"" + value + "\""
                                                     : value;
        if (!array.empty() && array == open_array && object == open_object) {
          line += ", " + json_value;
          continue;
        }
        close();
        if (object != open_object) {
          if (!open_object.empty()) line += "}";
          if (!object.empty()) {
            line += std::string(first ? "" : ", ") + "\"" + object + "\": {";
            first = true;
          }
          open_object = object;
        }
        line += std::string(first ? "" : ", ") + "\"" + (array.empty() ? key : array) + "\": ";
        first = false;
        if (!array.empty()) {
          line += "[" + json_value;
          open_array = array;
        } else {
          line += json_value;
        }
      }
      close();
      if (!open_object.empty()) line += "}";
      text += line + "}\n";
    }
    return text;
  }
  const std::string separator = v.dialect == "csv_semicolon" ? ";" : ",";
  if (v.dialect == "csv_semicolon") text += "\xEF\xBB\xBF";
  for (size_t i = 0; i < rows.front().size(); ++i) {
    // Headers quoted like a spreadsheet does when they hold its separator or brackets.
    text += (i ? separator : "") + ("\"" + rows.front()[i].first + "\"");
  }
  text += "\r\n";
  for (const auto& row : rows) {
    for (size_t i = 0; i < row.size(); ++i) text += (i ? separator : "") + row[i].second;
    text += "\r\n";
  }
  return text;
}

// The column names of a group in the variant's dialect ("cam1.tool.x" nests in JSON lines).
std::string Group(const std::string& camera, const std::string& target, const Variant& v) {
  if (!v.wide) return "";
  return v.dialect == "jsonl" ? camera + "_" + target + "." : camera + "_" + target + "_";
}

// Writes `truth` as the variant's table and mapping into `dir`; returns the mapping's path.
std::string WriteVariant(const Recording& truth, const Variant& v, const std::string& dir) {
  const bool json = v.dialect == "jsonl";
  auto joint = [&](int j) {
    return json ? "q[" + std::to_string(j) + "]" : "q" + std::to_string(j + 1);
  };
  const double angle = v.degrees ? 180.0 / M_PI : 1.0;
  auto sample_cells = [&](const Sample& s, Row* row) {
    row->push_back({"capture", "c" + std::to_string(s.id)});
    if (!v.poses_by_joints) row->push_back({"pose", "p" + std::to_string(s.pose)});
    for (size_t j = 0; j < s.q.size(); ++j) row->push_back({joint(j), Num(s.q[j] * angle, v)});
    row->push_back({"time", Num(*s.time_s * (v.fact_units ? 1000.0 : 1.0), v)});
    row->push_back({"temp", Num(*s.temperature_c + (v.fact_units ? 273.15 : 0.0), v)});
    row->push_back({"load", Num(*s.payload_kg * (v.fact_units ? 1000.0 : 1.0), v)});
  };
  auto pose_cells = [&](const Observation* o, const std::string& group, size_t index, Row* row) {
    const RotationColumns rc = RotationColumnsOf(v, group);
    std::vector<std::string> names;
    if (v.rotation != "transform" && v.rotation != "transform12") {
      for (const char* axis : {"x", "y", "z"}) names.push_back(group + axis);
    }
    names.insert(names.end(), rc.names.begin(), rc.names.end());
    const std::vector<double> cells = o ? PoseCells(*o, v, index % 2 == 1) : std::vector<double>();
    for (size_t i = 0; i < names.size(); ++i) {
      row->push_back({names[i], o ? Num(cells[i], v) : ""});
    }
  };
  std::vector<Row> rows;
  std::vector<std::pair<std::string, std::string>> groups;  // (camera, target) of a wide table
  if (v.wide) {
    for (const auto& camera : truth.cameras) {
      for (const auto& [target, carrier] : truth.targets) groups.emplace_back(camera, target);
    }
    for (const auto& s : truth.samples) {
      Row row;
      sample_cells(s, &row);
      for (const auto& [camera, target] : groups) {
        const Observation* seen = nullptr;
        for (const auto& o : truth.observations) {
          if (o.sample == s.id && o.camera == camera && o.target == target) seen = &o;
        }
        pose_cells(seen, Group(camera, target, v), s.id, &row);
      }
      rows.push_back(std::move(row));
    }
  } else {
    for (size_t i = 0; i < truth.observations.size(); ++i) {
      const Observation& o = truth.observations[i];
      Row row;
      sample_cells(truth.samples[truth.SampleIndex(o.sample)], &row);
      row.push_back({"camera", o.camera});
      row.push_back({"target", o.target});
      pose_cells(&o, "", i, &row);
      rows.push_back(std::move(row));
    }
  }
  const std::string table = json ? "table.jsonl" : "table.csv";
  testing::WriteText(dir + "/" + table, WriteTable(rows, v));

  std::ostringstream m;
  m << "mapping: cellmetry-import/1\n"
    << "description: " << v.name << "\n";
  if (v.dialect == "csv_semicolon") {
    m << "table: {path: " << table << ", decimal: \",\"}\n";  // the separator is detected
  } else {
    m << "table: " << table << "\n";
  }
  m << "units: {length: " << (v.metres ? "m" : "mm") << ", angle: " << (v.degrees ? "deg" : "rad")
    << "}\n";
  std::vector<std::string> joints;
  for (int j = 0; j < truth.robots.at("ur3"); ++j) joints.push_back(joint(j));
  m << "robot: {name: ur3, joints: " << List(joints) << "}\n";
  if (!v.wide) m << "samples: {column: capture}\n";
  m << (v.poses_by_joints ? "poses: {consecutive_joints: 0}\n" : "poses: {column: pose}\n");
  m << "targets: {tool: {on: ur3}, world: {on: world}}\n";
  m << "facts:\n"
    << "  time: " << (v.fact_units ? "{column: time, unit: ms}" : "time") << "\n"
    << "  temperature: {column: temp, unit: " << (v.fact_units ? "K" : "C") << "}\n"
    << "  payload: {column: load, unit: " << (v.fact_units ? "g" : "kg") << "}\n";
  m << "observations:\n";
  auto entry = [&](const std::string& camera, const std::string& target, const std::string& group) {
    const RotationColumns rc = RotationColumnsOf(v, group);
    m << "  - camera: " << camera << "\n    target: " << target << "\n";
    if (v.camera_in_target) m << "    pose_of: camera_in_target\n";
    if (v.rotation != "transform" && v.rotation != "transform12") {
      m << "    position: " << List({group + "x", group + "y", group + "z"}) << "\n";
    }
    if (!rc.mapping.empty()) m << "    " << rc.mapping << "\n";
  };
  if (v.wide) {
    for (const auto& [camera, target] : groups) entry(camera, target, Group(camera, target, v));
  } else {
    entry("{column: camera}", "{column: target}", "");
  }
  testing::WriteText(dir + "/mapping.yaml", m.str());
  return dir + "/mapping.yaml";
}

// The same recording, to 1e-9 in mm, rad, s, degC and kg.
void ExpectSameRecording(const Recording& read, const Recording& truth, bool rotations = true) {
  constexpr double kTolerance = 1e-9;
  EXPECT_EQ(read.robots, truth.robots);
  EXPECT_EQ(read.targets, truth.targets);
  std::vector<std::string> a = read.cameras, b = truth.cameras;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  ASSERT_EQ(read.samples.size(), truth.samples.size());
  for (size_t i = 0; i < truth.samples.size(); ++i) {
    const Sample& s = read.samples[i];
    const Sample& t = truth.samples[i];
    ASSERT_EQ(s.id, t.id);
    EXPECT_EQ(s.robot, t.robot);
    ASSERT_EQ(s.pose, t.pose) << "sample " << t.id;
    ASSERT_EQ(s.q.size(), t.q.size());
    for (size_t j = 0; j < t.q.size(); ++j) ASSERT_NEAR(s.q[j], t.q[j], kTolerance);
    for (const auto& [x, y] : {std::pair{s.time_s, t.time_s},
                               {s.temperature_c, t.temperature_c},
                               {s.payload_kg, t.payload_kg}}) {
      ASSERT_EQ(x.has_value(), y.has_value());
      if (x) {
        ASSERT_NEAR(*x, *y, kTolerance);
      }
    }
  }
  auto sorted = [](std::vector<Observation> list) {
    std::stable_sort(list.begin(), list.end(), [](const Observation& p, const Observation& q) {
      return std::tie(p.sample, p.camera, p.target) < std::tie(q.sample, q.camera, q.target);
    });
    return list;
  };
  const std::vector<Observation> got = sorted(read.observations), want = sorted(truth.observations);
  ASSERT_EQ(got.size(), want.size());
  double worst_mm = 0, worst_rad = 0;
  for (size_t i = 0; i < want.size(); ++i) {
    ASSERT_EQ(got[i].sample, want[i].sample);
    ASSERT_EQ(got[i].camera, want[i].camera);
    ASSERT_EQ(got[i].target, want[i].target);
    worst_mm = std::max(worst_mm, (got[i].position_mm - want[i].position_mm).cwiseAbs().maxCoeff());
    ASSERT_EQ(got[i].rvec.has_value(), rotations);
    if (rotations) {
      worst_rad = std::max(worst_rad, AngleBetween(RotationFromRvec(got[i].rvec->data()),
                                                   RotationFromRvec(want[i].rvec->data())));
    }
  }
  EXPECT_LE(worst_mm, kTolerance);
  EXPECT_LE(worst_rad, kTolerance);
  char worst[64];
  std::snprintf(worst, sizeof(worst), "%.2e mm, %.2e rad", worst_mm, worst_rad);
  ::testing::Test::RecordProperty("worst_difference", worst);
}

// configs/simulations/ur3_two_cameras.yaml with two captures per pose, a clock and payloads:
// every kind of fact and repeated poses. Simulated once for the suite.
class ImportEveryConvention : public ::testing::TestWithParam<Variant> {
 public:
  static void SetUpTestSuite() {
    // One folder per process: CTest runs each test as its own process, several at once, and a
    // shared folder was removed under a sibling's feet (its tests then reported as skipped).
    const std::string dir = testing::TempDir("import/truth_" + std::to_string(::getpid()));
    std::string spec =
        testing::ReadText(testing::Source("configs/simulations/ur3_two_cameras.yaml"));
    spec = testing::ReplaceOnce(
        spec, "../robots/ur3_vsb2020.yaml",
        testing::Source("configs/robots/ur3_vsb2020.yaml") + "\n    payloads_kg: [0, 0.75, 1.5]");
    spec = testing::ReplaceOnce(spec, "../../tests/data/vsb/sim_b",
                                testing::Source("tests/data/vsb/sim_b"));
    spec = testing::ReplaceOnce(spec, "repeats: 1", "repeats: 2");
    spec +=
        "timeline: {seconds_per_sample: 2.5, temperature_start_c: 20.5, temperature_end_c: 27}\n";
    testing::WriteText(dir + "/spec.yaml", spec);
    const auto r = testing::RunCellmetry("simulate " + dir + "/spec.yaml -o " + dir + "/recording");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    truth_ = new Recording(ReadRecording(dir + "/recording"));
  }
  static void TearDownTestSuite() {
    delete truth_;
    truth_ = nullptr;
  }

 protected:
  static const Recording* truth_;
};
const Recording* ImportEveryConvention::truth_ = nullptr;

TEST_P(ImportEveryConvention, GivesTheSimulatedRecordingTo1e9) {
  ASSERT_NE(truth_, nullptr);
  ASSERT_GT(truth_->observations.size(), 1000u);
  const Variant& v = GetParam();
  const std::string dir = testing::TempDir("import/" + v.name);
  const Recording imported = ImportRecording(WriteVariant(*truth_, v, dir));
  ExpectSameRecording(imported, *truth_, v.rotation != "position");
}

std::vector<Variant> Variants() {
  std::vector<Variant> list;
  // Every Euler order, both ways, alternating units and dialects.
  int n = 0;
  for (const char* order : kEulerOrders) {
    for (bool intrinsic : {true, false}) {
      Variant v;
      v.name = std::string("euler_") + order + (intrinsic ? "_intrinsic" : "_extrinsic");
      v.rotation = order;
      v.intrinsic = intrinsic;
      v.metres = n % 2 == 0;
      v.degrees = n % 3 != 0;
      v.dialect = n % 4 == 1 ? "csv_semicolon" : n % 4 == 3 ? "jsonl" : "csv";
      v.wide = n % 5 == 2;
      list.push_back(v);
      ++n;
    }
  }
  auto add = [&](const std::string& name, const std::string& rotation, auto&& setup) {
    Variant v;
    v.name = name;
    v.rotation = rotation;
    setup(v);
    list.push_back(v);
  };
  add("rpy_degrees_metres", "rpy", [](Variant& v) { v.degrees = v.metres = true; });
  add("rpy_radians_wide_jsonl", "rpy", [](Variant& v) {
    v.wide = true;
    v.dialect = "jsonl";
  });
  add("quaternion_wxyz_mm", "wxyz", [](Variant&) {});
  add("quaternion_xyzw_metres_semicolon", "xyzw", [](Variant& v) {
    v.metres = true;
    v.dialect = "csv_semicolon";
  });
  add("rotation_vector_mm_rad", "rotvec", [](Variant& v) { v.poses_by_joints = true; });
  add("rotation_vector_degrees_facts_in_ms_K_g", "rotvec", [](Variant& v) {
    v.degrees = true;
    v.fact_units = true;
  });
  add("matrix_3x3_named_columns", "matrix", [](Variant& v) { v.metres = true; });
  add("matrix_3x3_prefix_wide", "matrix_prefix", [](Variant& v) { v.wide = true; });
  add("transform_4x4_prefix", "transform", [](Variant& v) { v.metres = true; });
  add("transform_top_rows_jsonl", "transform12", [](Variant& v) { v.dialect = "jsonl"; });
  add("position_only_dots", "position", [](Variant& v) { v.metres = true; });
  add("camera_in_target_quaternion", "xyzw", [](Variant& v) { v.camera_in_target = true; });
  add("camera_in_target_transform_wide", "transform", [](Variant& v) {
    v.camera_in_target = true;
    v.wide = true;
    v.poses_by_joints = true;
  });
  return list;
}

INSTANTIATE_TEST_SUITE_P(Tables, ImportEveryConvention, ::testing::ValuesIn(Variants()),
                         [](const ::testing::TestParamInfo<Variant>& info) {
                           return info.param.name;
                         });

// Through the command line: the folder carries the marker and the mapping, reads back as the
// truth, and a second import replaces it (keeping the first as .previous).
TEST_F(ImportEveryConvention, CommandWritesAMarkedRecordingThatReadsBack) {
  ASSERT_NE(truth_, nullptr);
  const std::string dir = testing::TempDirForThisTest("import");
  Variant v;
  v.name = "cli";
  v.rotation = "ZYX";
  v.intrinsic = true;
  v.degrees = true;
  v.metres = true;
  const std::string mapping = WriteVariant(*truth_, v, dir);
  const std::string out = dir + "/recording";
  auto r = testing::RunCellmetry("import " + mapping + " -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("imported 2008 rows of table.csv: 502 samples at 251 poses, "
                                  "2008 observations of 2 targets by 2 cameras"));
  EXPECT_THAT(testing::ReadText(out + "/.cellmetry-output"), HasSubstr("kind: recording"));
  EXPECT_THAT(testing::ReadText(out + "/import.yaml"), HasSubstr("axes: intrinsic"));
  ExpectSameRecording(ReadRecording(out), *truth_);
  r = testing::RunCellmetry("import " + mapping + " -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out + ".previous/samples.csv"));
}

// The example docs/your-data.md walks through: the spreadsheet excerpt of VSB experiment A
// imports to the bundled recording's numbers, and its job finds the measured placement.
TEST(BundledExample, SpreadsheetExcerptImportsToTheBundledRecordingAndItsJobRuns) {
  const Recording imported =
      ImportRecording(testing::Source("configs/import/vsb_exp_a_excerpt.yaml"));
  const Recording exp_a = ReadRecording(testing::Source("tests/data/vsb/exp_a"));
  ASSERT_EQ(imported.samples.size(), 96u);
  ASSERT_EQ(imported.observations.size(), 576u);
  // Imported sample i is the i-th capture the table names; capture ids are exp_a's sample ids.
  const DataTable table = ReadCsvTable(testing::Source("configs/import/vsb_exp_a_excerpt.csv"), {});
  std::vector<int> capture;
  for (size_t row = 0; row < table.num_rows(); ++row) {
    const int id = static_cast<int>(table.Number(row, *table.ColumnIndex("capture")));
    if (capture.empty() || capture.back() != id) capture.push_back(id);
  }
  ASSERT_EQ(capture.size(), imported.samples.size());
  double worst_mm = 0, worst_rad = 0;
  for (const auto& o : imported.observations) {
    const Sample& original = exp_a.samples[exp_a.SampleIndex(capture[o.sample])];
    EXPECT_EQ(imported.samples[o.sample].q, original.q);
    EXPECT_EQ(imported.samples[o.sample].pose, original.pose / 8);
    const auto match = std::find_if(
        exp_a.observations.begin(), exp_a.observations.end(), [&](const Observation& e) {
          return e.sample == original.id && e.camera == o.camera && e.target == o.target;
        });
    ASSERT_NE(match, exp_a.observations.end());
    worst_mm = std::max(worst_mm, (o.position_mm - match->position_mm).cwiseAbs().maxCoeff());
    worst_rad = std::max(worst_rad, AngleBetween(RotationFromRvec(o.rvec->data()),
                                                 RotationFromRvec(match->rvec->data())));
  }
  EXPECT_LT(worst_mm, 1e-9);
  EXPECT_LT(worst_rad, 1e-8);  // the table's angles carry 7 decimals of a degree
  // Its job, on the imported recording: the base within 3 sigma of the measured placement.
  const WorkcellJob job = LoadWorkcellJob(testing::Source("configs/jobs/vsb_exp_a_excerpt.yaml"),
                                          testing::Plugins(), /*recording_must_exist=*/false);
  ValidateJobAgainstRecording(job, imported);
  const WorkcellResult result = testing::Identify(job, imported);
  const FrameEstimate& base = testing::Frame(result, "ur3.base");
  const Eigen::Vector3d placement(431.0, 555.0, -460.0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(base.pose.t[i] - placement[i]), 3 * base.sigma_mm[i]) << "xyz"[i];
  }
  EXPECT_THAT(WorkcellSummary(result),
              HasSubstr("(spread of 3 repeated captures at each of 32 poses)"));
}

}  // namespace
}  // namespace cellmetry
