// Bad mappings and bad tables through `cellmetry import`: every case gets one error line naming
// the file, line and column and what to do, exit code 2, and no recording folder.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/recording.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;
using testing::ReplaceOnce;

std::string Num(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

// The first three samples of VSB sim_b as a spreadsheet would hold them (one row per sample,
// camera and target; the rotation as vector, quaternion and matrix), and a mapping for it.
class BadMapping : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDirForThisTest("import_bad_mapping");
    table_ = dir_ + "/t.csv";
    mapping_ = dir_ + "/map.yaml";
    output_ = dir_ + "/recording";
    const Recording sim_b = ReadRecording(testing::Source("tests/data/vsb/sim_b"));
    std::ostringstream t;
    // columns: 1 capture, 2 pose, 3-8 q1-q6, 9 camera, 10 target, 11-13 x y z, 14-16 rx ry rz,
    // 17-20 qw qx qy qz, 21-29 R11 .. R33
    t << "capture,pose,q1,q2,q3,q4,q5,q6,camera,target,x,y,z,rx,ry,rz,qw,qx,qy,qz,"
         "R11,R12,R13,R21,R22,R23,R31,R32,R33\n";
    for (const auto& o : sim_b.observations) {
      if (o.sample > 2) break;
      const Sample& s = sim_b.samples[sim_b.SampleIndex(o.sample)];
      t << "c" << s.id << ",p" << s.pose;
      for (double q : s.q) t << "," << Num(q);
      t << "," << o.camera << "," << o.target;
      for (int i = 0; i < 3; ++i) t << "," << Num(o.position_mm[i]);
      for (int i = 0; i < 3; ++i) t << "," << Num((*o.rvec)[i]);
      const Eigen::Matrix3d R = RotationFromRvec(o.rvec->data());
      const Eigen::Quaterniond q(R);
      for (double v : {q.w(), q.x(), q.y(), q.z()}) t << "," << Num(v);
      for (int i = 0; i < 9; ++i) t << "," << Num(R(i / 3, i % 3));
      t << "\n";
    }
    testing::WriteText(table_, t.str());
  }

  // Line numbers and columns matter to the tests.
  static std::string MappingText() {
    return "mapping: cellmetry-import/1\n"                                          // 1
           "description: bad mapping tests\n"                                       // 2
           "table: t.csv\n"                                                         // 3
           "units: {length: mm, angle: rad}\n"                                      // 4
           "robot: {name: ur3, joints: [q1, q2, q3, q4, q5, q6]}\n"                 // 5
           "samples: {column: capture}\n"                                           // 6
           "poses: {column: pose}\n"                                                // 7
           "targets: {tool: {on: ur3}, world: {on: world}}\n"                       // 8
           "observations:\n"                                                        // 9
           "  - camera: {column: camera}\n"                                         // 10
           "    target: {column: target}\n"                                         // 11
           "    position: [x, y, z]\n"                                              // 12
           "    rotation: {convention: rotation_vector, columns: [rx, ry, rz]}\n";  // 13
  }

  // Replaces cell `column` (1-based) of line `line` of the table; "+=0.01" adds to its number,
  // "*=-1" multiplies it.
  void EditCell(int line, int column, const std::string& value) {
    std::istringstream in(testing::ReadText(table_));
    std::string text;
    int n = 0;
    for (std::string row; std::getline(in, row);) {
      if (++n == line) {
        std::vector<std::string> cells;
        std::stringstream split(row);
        for (std::string cell; std::getline(split, cell, ',');) cells.push_back(cell);
        std::string& cell = cells.at(column - 1);
        if (value.rfind("+=", 0) == 0) {
          cell = Num(std::stod(cell) + std::stod(value.substr(2)));
        } else if (value.rfind("*=", 0) == 0) {
          cell = Num(std::stod(cell) * std::stod(value.substr(2)));
        } else {
          cell = value;
        }
        row.clear();
        for (size_t i = 0; i < cells.size(); ++i) row += (i ? "," : "") + cells[i];
      }
      text += row + "\n";
    }
    testing::WriteText(table_, text);
  }

  testing::CommandResult Import() {
    return testing::RunCellmetry("import " + mapping_ + " -o " + output_);
  }

  void ExpectRejected(const testing::CommandResult& r, const std::string& location,
                      const std::string& hint) {
    testing::ExpectOneLineError(r, location, hint);
    EXPECT_FALSE(fs::exists(output_)) << "a recording folder was written";
    for (const auto& entry : fs::directory_iterator(dir_)) {
      EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
    }
  }

  std::string dir_, table_, mapping_, output_;
};

TEST_F(BadMapping, TheUnbrokenMappingImports) {
  testing::WriteText(mapping_, MappingText());
  const auto r = Import();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Recording imported = ReadRecording(output_);
  EXPECT_EQ(imported.samples.size(), 3u);
  EXPECT_EQ(imported.observations.size(), 6u);
}

// One broken mapping or table, and the error it must produce.
struct Breakage {
  std::string name;
  std::string from, to;                                  // in the mapping text ("" = unchanged)
  std::vector<std::tuple<int, int, std::string>> cells;  // table (line, column, new text)
  std::string location;                                  // file:line:column:
  std::string hint;
  std::string message;
};

void PrintTo(const Breakage& b, std::ostream* out) { *out << b.name; }

class BrokenImport : public BadMapping, public ::testing::WithParamInterface<Breakage> {};

TEST_P(BrokenImport, IsRejectedWhereItIs) {
  const Breakage& b = GetParam();
  testing::WriteText(mapping_,
                     b.from.empty() ? MappingText() : ReplaceOnce(MappingText(), b.from, b.to));
  for (const auto& [line, column, text] : b.cells) EditCell(line, column, text);
  const auto r = Import();
  ExpectRejected(r, b.location, b.hint);
  EXPECT_THAT(r.output, HasSubstr(b.message));
}

const char kQuaternion[] = "{convention: quaternion, order: wxyz, columns: [qw, qx, qy, qz]}";
const char kMatrix[] = "{convention: matrix, prefix: R}";
const char kRotvec[] = "{convention: rotation_vector, columns: [rx, ry, rz]}";

INSTANTIATE_TEST_SUITE_P(
    Import, BrokenImport,
    ::testing::Values(
        // The mapping.
        Breakage{"UnknownColumnNamesTheNearest",
                 "[x, y, z]",
                 "[x, y, zz]",
                 {},
                 "map.yaml:12:22:",
                 "Did you mean 'z'?",
                 "column 'zz' is not in the table"},
        Breakage{"UnknownJointColumn",
                 "q5, q6]",
                 "q5, joint6]",
                 {},
                 "map.yaml:5:49:",
                 "The table's columns are: capture, pose, q1",
                 "column 'joint6' is not in the table"},
        Breakage{"MissingUnits",
                 "units: {length: mm, angle: rad}\n",
                 "",
                 {},
                 "map.yaml:1:1:",
                 "Say the table's units: units: {length: m, angle: deg}",
                 "missing key 'units'"},
        Breakage{"MissingAngleUnit",
                 "angle: rad}",
                 "}",
                 {},
                 "map.yaml:4:8:",
                 "Add angle: rad or angle: deg",
                 "units: missing key 'angle'"},
        Breakage{"UnknownLengthUnit",
                 "length: mm",
                 "length: cm",
                 {},
                 "map.yaml:4:17:",
                 "Did you mean 'mm'?",
                 "unknown length unit 'cm'"},
        Breakage{"MissingJoints",
                 ", joints: [q1, q2, q3, q4, q5, q6]",
                 "",
                 {},
                 "map.yaml:5:8:",
                 "List the joint readings' columns",
                 "robot: missing key 'joints'"},
        Breakage{"MisspeltKey",
                 "observations:",
                 "observation:",
                 {},
                 "map.yaml:9:1:",
                 "Did you mean 'observations'?",
                 "observation: unknown key"},
        Breakage{"UnknownConvention",
                 "rotation_vector,",
                 "rotation_vectr,",
                 {},
                 "map.yaml:13:28:",
                 "Did you mean 'rotation_vector'?",
                 "unknown rotation convention 'rotation_vectr'"},
        Breakage{"LowercaseEulerOrder",
                 kRotvec,
                 "{convention: euler, order: xyz, axes: extrinsic, columns: [rx, ry, rz]}",
                 {},
                 "map.yaml:13:42:",
                 "Write three capital axes",
                 "'xyz' is not an Euler sequence"},
        Breakage{"EulerWithoutAxes",
                 kRotvec,
                 "{convention: euler, order: ZYX, columns: [rx, ry, rz]}",
                 {},
                 "map.yaml:13:15:",
                 "(axes: intrinsic) or the fixed frame's (axes: extrinsic)",
                 "missing key 'axes'"},
        Breakage{"QuaternionWithoutOrder",
                 kRotvec,
                 "{convention: quaternion, columns: [qw, qx, qy, qz]}",
                 {},
                 "map.yaml:13:15:",
                 "order: wxyz (scalar first) or order: xyzw",
                 "missing key 'order'"},
        Breakage{"WrongColumnCount",
                 "[x, y, z]",
                 "[x, y]",
                 {},
                 "map.yaml:12:15:",
                 "List the columns of x, y, z",
                 "position: expected 3 column names"},
        Breakage{"TargetNotListed",
                 "    target: {column: target}",
                 "    target: gripper",
                 {},
                 "map.yaml:11:13:",
                 "List it under targets:",
                 "target 'gripper' is not under targets:"},
        Breakage{"UnknownEncoding",
                 "table: t.csv",
                 "table: {path: t.csv, encoding: utf-16}",
                 {},
                 "map.yaml:3:32:",
                 "Known: utf-8, latin1, windows-1252, cp1252",
                 "unknown text encoding 'utf-16'"},
        Breakage{"TableAndTables",
                 "table: t.csv\n",
                 "table: t.csv\ntables: {a: t.csv, b: t.csv}\n",
                 {},
                 "map.yaml:1:1:",
                 "or, for several, tables: {robot: joints.csv, tracker: tracker.csv}",
                 "give table: or tables:, not both"},
        Breakage{"TablesWithoutJoin",
                 "table: t.csv",
                 "tables: {a: t.csv, b: t.csv}",
                 {},
                 "map.yaml:1:1:",
                 "Say how the tables' rows belong together: join: {by: row}",
                 "missing key 'join'"},
        Breakage{"JoinTimeColumnOfATableNotListed",
                 "table: t.csv",
                 "tables: {a: t.csv, b: t.csv}\n"
                 "join: {by: time, columns: {a: capture, c: capture}, tolerance_s: 0}",
                 {},
                 "map.yaml:4:43:",
                 "Tables: a, b",
                 "'c' is not under tables:"},
        Breakage{"UncertaintyLevelWithoutACoverageFactor",
                 "    position: [x, y, z]\n",
                 "    position: [x, y, z]\n"
                 "    position_uncertainty: {columns: [x, y, z], level: 95}\n",
                 {},
                 "map.yaml:13:55:",
                 "one of GUM Table G.1's: 0.6827, 0.90, 0.95",
                 "no coverage factor for the level 95"},
        Breakage{"TableNotThere",
                 "table: t.csv",
                 "table: nope.csv",
                 {},
                 "map.yaml:3:8:",
                 "relative to the mapping file",
                 "no table at"},
        // The table's cells.
        Breakage{"NonNumericCell",
                 "",
                 "",
                 {{3, 11, "abc"}},
                 "t.csv:3:11:",
                 "Write a plain decimal number",
                 "column 'x' of data row 2: 'abc' is not a number"},
        Breakage{"DecimalCommaNotAnnounced",
                 "",
                 "",
                 {{3, 11, "\"519,26\""}},
                 "t.csv:3:11:",
                 "table: {decimal: \",\"}",
                 "'519,26' is not a number"},
        Breakage{"InfiniteCell",
                 "",
                 "",
                 {{4, 12, "inf"}},
                 "t.csv:4:12:",
                 "Write a plain decimal number",
                 "'inf' is not a finite number"},
        Breakage{"NotOrthonormalMatrix",
                 kRotvec,
                 kMatrix,
                 {{5, 22, "+=0.01"}},
                 "t.csv:5:21:",
                 "raise tolerance:",
                 "column 'R11' of data row 4: the matrix is not orthonormal"},
        Breakage{"MirroredMatrix",
                 kRotvec,
                 kMatrix,
                 {{5, 27, "*=-1"}, {5, 28, "*=-1"}, {5, 29, "*=-1"}},
                 "t.csv:5:21:",
                 "raise tolerance:",
                 "determinant is -1: a mirrored frame"},
        Breakage{"QuaternionNotUnit",
                 kRotvec,
                 kQuaternion,
                 {{2, 17, "2"}},
                 "t.csv:2:17:",
                 "Check the four cells and their order (quaternion wxyz)",
                 "the quaternion's length is"},
        Breakage{"PartlyFilledObservation",
                 "",
                 "",
                 {{6, 15, ""}},
                 "t.csv:6:15:",
                 "leave all of them empty where the target was not seen",
                 "the observation of 'tool' in 'cam1' is partly filled in"},
        Breakage{"UnknownTargetInACell",
                 "",
                 "",
                 {{2, 10, "tol"}},
                 "t.csv:2:10:",
                 "Did you mean 'tool'?",
                 "unknown target 'tol'"},
        Breakage{"RowsOfOneSampleDisagree",
                 "",
                 "",
                 {{3, 4, "3.5"}},
                 "t.csv:3:4:",
                 "The rows of one sample are one robot state",
                 "sample 'c0' (data row 1) has 3.485526323 rad there but 3.5 rad here"},
        Breakage{"JointsInDegreesDeclaredRadians",
                 "",
                 "",
                 {{2, 3, "270.94"}},
                 "t.csv:2:3:",
                 "if they are degrees, say robot: {angle: deg}",
                 "'270.94' is beyond any measurement of it"},
        Breakage{"AnglesInDegreesDeclaredRadians",
                 "",
                 "",
                 {{2, 14, "129.97"}},
                 "t.csv:2:14:",
                 "if they are degrees, say units: {angle: deg}",
                 "column 'rx' of data row 1: '129.97 rad' is more than a full turn"},
        Breakage{"PositionInMetresBeyondAnyMeasurement",
                 "length: mm",
                 "length: m",
                 {},
                 "t.csv:2:11:",
                 "if the table holds millimetres, say units: {length: mm}",
                 "'244.63286400000001' is beyond any measurement of it"},
        Breakage{"UnclosedQuote",
                 "",
                 "",
                 {{7, 9, "\"cam1"}},
                 "t.csv:7:9:",
                 "Close the quote",
                 "a quoted field is never closed"}),
    [](const ::testing::TestParamInfo<Breakage>& info) { return info.param.name; });

TEST_F(BadMapping, JsonLinesSyntaxErrorIsPlacedAtItsCharacter) {
  testing::WriteText(dir_ + "/t.jsonl",
                     "{\"capture\": 1, \"q1\": 0.5}\n"
                     "{\"capture\": 2, \"q1\": 0.5,, \"q2\": 1}\n");
  testing::WriteText(mapping_, ReplaceOnce(MappingText(), "table: t.csv", "table: t.jsonl"));
  ExpectRejected(Import(), "t.jsonl:2:26:", "Write one JSON object per line");
}

// A JSON-lines table read as written or refused at its line: nothing nlohmann's parser takes
// that no table means (a key twice: one of them lost; a value nested 20,000 deep: a crash in
// the flattening; 1e400: "internal error: number overflow").
struct JsonLine {
  std::string name;
  std::string line;  // the table's second line
  std::string location, message, hint;
};

void PrintTo(const JsonLine& j, std::ostream* out) { *out << j.name; }

class BadJsonLine : public BadMapping, public ::testing::WithParamInterface<JsonLine> {};

TEST_P(BadJsonLine, IsRefusedAtItsLine) {
  const JsonLine& j = GetParam();
  testing::WriteText(dir_ + "/t.jsonl", "{\"capture\": 1, \"q1\": 0.5}\n" + j.line + "\n");
  testing::WriteText(mapping_, ReplaceOnce(MappingText(), "table: t.csv", "table: t.jsonl"));
  const auto r = Import();
  ExpectRejected(r, j.location, j.hint);
  EXPECT_THAT(r.output, HasSubstr(j.message));
}

INSTANTIATE_TEST_SUITE_P(
    JsonLines, BadJsonLine,
    ::testing::Values(
        JsonLine{"KeyTwice", "{\"capture\": 2, \"q1\": 0.5, \"q1\": 0.7}",
                 "t.jsonl:2:", "key 'q1' appears twice in one object", "Keep one of them"},
        JsonLine{"KeyTwiceInANestedObject",
                 "{\"capture\": 2, \"pose\": {\"t\": [1, 2, 3], \"t\": [4, 5, 6]}}",
                 "t.jsonl:2:", "key 't' appears twice in one object", "Keep one of them"},
        JsonLine{"NestedTwentyThousandDeep",
                 "{\"q1\": " + std::string(20000, '[') + std::string(20000, ']') + "}",
                 "t.jsonl:2:", "objects and arrays nested deeper than 64 levels",
                 "A row's values nest a few levels at most"},
        JsonLine{"NumberBeyondADouble", "{\"capture\": 2, \"q1\": 1e400}",
                 "t.jsonl:2:22:", "'1e400' is beyond the range of a number",
                 "Write the value in the units the mapping declares"},
        JsonLine{
            "OverlongKeyTwiceIsQuotedShort",
            "{\"" + std::string(100000, 'k') + "\": 1, \"" + std::string(100000, 'k') + "\": 2}",
            "t.jsonl:2:", "key '" + std::string(77, 'k') + "...' appears twice",
            "Keep one of them"}),
    [](const ::testing::TestParamInfo<JsonLine>& info) { return info.param.name; });

// An error line quotes at most 80 characters of a cell: a 10 MB cell was echoed whole.
TEST_F(BadMapping, AnOverlongCellIsQuotedShort) {
  testing::WriteText(mapping_, MappingText());
  EditCell(3, 11, "0." + std::string(1000000, '7') + "x");
  const auto r = Import();
  ExpectRejected(r, "t.csv:3:11:", "Write a plain decimal number");
  EXPECT_THAT(r.output, HasSubstr("'0." + std::string(78, '7') + "...' is not a number"));
  EXPECT_LT(r.output.size(), 1000u);
}

TEST_F(BadMapping, ATableThatIsAFifoIsRefusedAtOnce) {
  ASSERT_EQ(::mkfifo((dir_ + "/t.jsonl").c_str(), 0600), 0);
  testing::WriteText(mapping_, ReplaceOnce(MappingText(), "table: t.csv", "table: t.jsonl"));
  ExpectRejected(Import(), "t.jsonl:", "Put a regular file there");
  fs::remove(table_);
  ASSERT_EQ(::mkfifo(table_.c_str(), 0600), 0);
  testing::WriteText(mapping_, MappingText());
  ExpectRejected(Import(), "t.csv:", "Put a regular file there");
}

TEST_F(BadMapping, AFolderCellmetryDidNotWriteIsLeftAlone) {
  testing::WriteText(mapping_, MappingText());
  testing::WriteText(output_ + "/notes.txt", "mine\n");
  const auto r = Import();
  testing::ExpectOneLineError(r, output_ + ":", "remove it yourself");
  EXPECT_EQ(testing::ReadText(output_ + "/notes.txt"), "mine\n");
  EXPECT_FALSE(fs::exists(output_ + "/samples.csv"));
}

}  // namespace
}  // namespace cellmetry
