// The recording folder format: reading the shipped data, writing and reading back, units.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cellmetry/formats/csv_table.h"
#include "cellmetry/formats/recording.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ReadRecording, SimBHasTheRecordedSamplesObservationsCamerasAndTargets) {
  const Recording r = ReadRecording(testing::Source("tests/data/vsb/sim_b"));
  EXPECT_EQ(r.samples.size(), 251u);
  EXPECT_EQ(r.observations.size(), 502u);
  EXPECT_EQ(r.cameras, (std::vector<std::string>{"cam1"}));
  EXPECT_EQ(r.robots, (std::map<std::string, int>{{"ur3", 6}}));
  EXPECT_EQ(r.targets, (std::map<std::string, std::string>{{"tool", "ur3"}, {"world", "world"}}));
  EXPECT_FALSE(r.description.empty());
  EXPECT_TRUE(r.images.empty());
}

TEST(ReadRecording, SimBJointValuesAreThoseInTheCsv) {
  const Recording r = ReadRecording(testing::Source("tests/data/vsb/sim_b"));
  // samples.csv line 2 and line 5.
  const Sample& first = r.samples.front();
  EXPECT_EQ(first.id, 0);
  EXPECT_EQ(first.robot, "ur3");
  EXPECT_EQ(first.pose, 0);
  EXPECT_EQ(first.q, (std::vector<double>{4.728881836, 3.485526323, 0.5406000614, 4.202291489,
                                          5.030451298, 0.6721514463}));
  const Sample& fourth = r.samples[3];
  EXPECT_EQ(fourth.id, 3);
  EXPECT_EQ(fourth.pose, 3);
  EXPECT_EQ(fourth.q, (std::vector<double>{4.700736523, 3.39327383, 0.7314307094, 4.095294476,
                                           5.03745842, 0.6946150661}));
  EXPECT_FALSE(first.time_s.has_value());
  EXPECT_FALSE(first.temperature_c.has_value());
  EXPECT_FALSE(first.payload_kg.has_value());
}

TEST(ReadRecording, SimBObservationsKeepPositionRotationAndLine) {
  const Recording r = ReadRecording(testing::Source("tests/data/vsb/sim_b"));
  const Observation& tool = r.observations[0];
  EXPECT_EQ(tool.sample, 0);
  EXPECT_EQ(tool.camera, "cam1");
  EXPECT_EQ(tool.target, "tool");
  EXPECT_EQ(tool.position_mm, Eigen::Vector3d(244.632864, -55.383274, 725.424014));
  ASSERT_TRUE(tool.rvec.has_value());
  EXPECT_EQ(*tool.rvec, Eigen::Vector3d(-2.155004972, 1.601929886, 0.536612874));
  EXPECT_EQ(tool.line, 2);
  EXPECT_EQ(r.observations[1].target, "world");
  EXPECT_EQ(r.observations[1].line, 3);
  for (const auto& obs : r.observations) EXPECT_GE(r.SampleIndex(obs.sample), 0);
}

// A recording with two robots of different joint counts, optional columns filled in only for
// some samples, position-only observations and an image list: every feature of the format.
Recording SmallRecording() {
  Recording r;
  r.description = "round trip: two robots, \"quoted\" text";
  r.robots = {{"ur3", 6}, {"delta", 3}};
  r.cameras = {"cam1", "cam2"};
  r.targets = {{"tool", "ur3"}, {"effector", "delta"}, {"world", "world"}};
  Sample a;
  a.id = 0;
  a.robot = "ur3";
  a.pose = 0;
  a.q = {0.125, -1.5, 2.75, 3.0625, -0.0001234, 6.2831853};
  a.time_s = 0.5;
  a.temperature_c = 21.25;
  Sample b;
  b.id = 1;
  b.robot = "ur3";
  b.pose = 0;
  b.q = {0.126, -1.5, 2.75, 3.0625, -0.0001234, 6.2831853};
  b.payload_kg = 1.5;
  Sample c;
  c.id = 7;
  c.robot = "delta";
  c.pose = 3;
  c.q = {0.3, -0.2, 0.1};
  r.samples = {a, b, c};
  Observation tool;
  tool.sample = 0;
  tool.camera = "cam1";
  tool.target = "tool";
  tool.position_mm = Eigen::Vector3d(244.632864, -55.383274, 725.424014);
  tool.rvec = Eigen::Vector3d(-2.155004972, 1.601929886, 0.536612874);
  // As `cellmetry detect` measures it: with the covariances of its position and rotation.
  tool.covariance_mm2 =
      (Eigen::Matrix3d() << 0.04, 0.001, -0.002, 0.001, 0.05, 0.003, -0.002, 0.003, 0.4).finished();
  tool.rotation_covariance_rad2 =
      (Eigen::Matrix3d() << 1e-7, 2e-9, 0, 2e-9, 3e-7, -1e-9, 0, -1e-9, 5e-8).finished();
  Observation dot;  // a triangulated dot: position only
  dot.sample = 7;
  dot.camera = "cam2";
  dot.target = "effector";
  dot.position_mm = Eigen::Vector3d(-12.5, 0.0, 1000.25);
  Observation world;
  world.sample = 1;
  world.camera = "cam2";
  world.target = "world";
  world.position_mm = Eigen::Vector3d(1, 2, 3);
  world.rvec = Eigen::Vector3d(0, 0, 0);
  r.observations = {tool, dot, world};
  r.images = {{0, "cam1", "left", "images/0_left.png"}, {7, "cam2", "mono", "images/7.png"}};
  return r;
}

void ExpectSameSamples(const std::vector<Sample>& read, const std::vector<Sample>& written) {
  ASSERT_EQ(read.size(), written.size());
  for (size_t i = 0; i < read.size(); ++i) {
    SCOPED_TRACE("sample " + std::to_string(i));
    EXPECT_EQ(read[i].id, written[i].id);
    EXPECT_EQ(read[i].robot, written[i].robot);
    EXPECT_EQ(read[i].pose, written[i].pose);
    EXPECT_EQ(read[i].q, written[i].q);
    EXPECT_EQ(read[i].time_s, written[i].time_s);
    EXPECT_EQ(read[i].temperature_c, written[i].temperature_c);
    EXPECT_EQ(read[i].payload_kg, written[i].payload_kg);
  }
}

void ExpectSameObservations(const std::vector<Observation>& read,
                            const std::vector<Observation>& written) {
  ASSERT_EQ(read.size(), written.size());
  for (size_t i = 0; i < read.size(); ++i) {
    SCOPED_TRACE("observation " + std::to_string(i));
    EXPECT_EQ(read[i].sample, written[i].sample);
    EXPECT_EQ(read[i].camera, written[i].camera);
    EXPECT_EQ(read[i].target, written[i].target);
    EXPECT_EQ(read[i].position_mm, written[i].position_mm);
    ASSERT_EQ(read[i].rvec.has_value(), written[i].rvec.has_value());
    if (written[i].rvec) {
      EXPECT_EQ(*read[i].rvec, *written[i].rvec);
    }
    ASSERT_EQ(read[i].covariance_mm2.has_value(), written[i].covariance_mm2.has_value());
    if (written[i].covariance_mm2) {
      EXPECT_EQ(*read[i].covariance_mm2, *written[i].covariance_mm2);
    }
    ASSERT_EQ(read[i].rotation_covariance_rad2.has_value(),
              written[i].rotation_covariance_rad2.has_value());
    if (written[i].rotation_covariance_rad2) {
      EXPECT_EQ(*read[i].rotation_covariance_rad2, *written[i].rotation_covariance_rad2);
    }
  }
}

// Text written by cellmetry's comparisons (table.csv) is read by the same reader as a recording:
// quoted cells keep their commas, and a doubled quote inside one is one quote (RFC 4180).
TEST(CsvTable, ParsesQuotedCellsFromText) {
  const CsvTable table =
      CsvTable::Parse("name,value\n\"a, b\",1\n\"say \"\"hi\"\"\",2\n", "table.csv");
  ASSERT_EQ(table.num_rows(), 2u);
  EXPECT_EQ(table.Text(0, "name"), "a, b");
  EXPECT_EQ(table.Text(1, "name"), "say \"hi\"");
  EXPECT_EQ(table.line_of(1), 3);
  EXPECT_TRUE(CsvTable::Parse("", "empty.csv").header().empty());
}

// A table read one row at a time: its rows counted before the first (blank and comment lines
// not), a byte-order mark and short rows as CsvTable reads them, each row at its line, and a
// table of more rows than the reader's limit refused before any row is read, the limit named.
TEST(CsvRows, ReadsOneRowAtATimeWithItsLineAndRefusesMoreThanItsLimit) {
  const std::string dir = testing::TempDir("recording/csv_rows");
  const std::string path = dir + "/table.csv";
  testing::WriteText(path, "\xEF\xBB\xBFname,value\n# a comment\n\"a, b\",1\n\n  \nc\n");
  CsvRows rows(path, 2, "Split it");
  EXPECT_EQ(rows.num_rows(), 2u);
  EXPECT_EQ(rows.header().front(), "name");
  ASSERT_TRUE(rows.Next());
  EXPECT_EQ(rows.line(), 3);
  EXPECT_EQ(rows.Text("name"), "a, b");
  EXPECT_EQ(rows.Integer("value"), 1);
  ASSERT_TRUE(rows.Next());
  EXPECT_EQ(rows.line(), 6);
  EXPECT_FALSE(rows.HasValue("value"));
  EXPECT_EQ(rows.OptionalNumber("value"), std::nullopt);
  EXPECT_FALSE(rows.Next());
  const std::string mark_alone = dir + "/mark_alone.csv";
  testing::WriteText(mark_alone, "\xEF\xBB\xBF\nname\nx\n");  // a line left empty: not a row
  CsvRows after_mark(mark_alone, 1, "Split it");
  EXPECT_EQ(after_mark.num_rows(), 1u);
  ASSERT_TRUE(after_mark.Next());
  EXPECT_EQ(after_mark.Text("name"), "x");
  try {
    CsvRows too_many(path, 1, "Split it");
    FAIL() << "two rows read under a limit of one";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, path);
    EXPECT_THAT(e.message(), ::testing::HasSubstr("has 2 rows, more than the 1 cellmetry reads"));
    EXPECT_EQ(e.hint(), "Split it");
  }
}

TEST(WriteRecording, ReadingBackGivesTheSameRecording) {
  const std::string folder = testing::TempDir("recording/round_trip") + "/rec";
  const Recording written = SmallRecording();
  WriteRecording(written, folder);
  const Recording read = ReadRecording(folder);
  EXPECT_EQ(read.folder, folder);
  EXPECT_EQ(read.description, written.description);
  EXPECT_EQ(read.robots, written.robots);
  EXPECT_EQ(read.cameras, written.cameras);
  EXPECT_EQ(read.targets, written.targets);
  ExpectSameSamples(read.samples, written.samples);
  ExpectSameObservations(read.observations, written.observations);
  ASSERT_EQ(read.images.size(), 2u);
  EXPECT_EQ(read.images[1].sample, 7);
  EXPECT_EQ(read.images[1].camera, "cam2");
  EXPECT_EQ(read.images[1].view, "mono");
  EXPECT_EQ(read.images[1].path, "images/7.png");
}

TEST(WriteRecording, SimBRoundTripsExactly) {
  const Recording original = ReadRecording(testing::Source("tests/data/vsb/sim_b"));
  const std::string folder = testing::TempDir("recording/sim_b_round_trip") + "/rec";
  WriteRecording(original, folder);
  const Recording read = ReadRecording(folder);
  EXPECT_EQ(read.description, original.description);
  ExpectSameSamples(read.samples, original.samples);
  ExpectSameObservations(read.observations, original.observations);
}

TEST(WriteRecording, OptionalColumnsAreWrittenOnlyWhenUsed) {
  Recording r = SmallRecording();
  for (auto& s : r.samples) s.time_s = s.temperature_c = s.payload_kg = std::nullopt;
  const std::string folder = testing::TempDir("recording/no_optional") + "/rec";
  WriteRecording(r, folder);
  const std::string samples = ReadText(folder + "/samples.csv");
  EXPECT_EQ(samples.substr(0, samples.find('\n')), "sample,robot,pose,q1,q2,q3,q4,q5,q6");
  EXPECT_FALSE(fs::exists(folder + "/truth.yaml"));
}

TEST(WriteRecording, TruthGoesToTruthYaml) {
  const std::string folder = testing::TempDir("recording/truth") + "/rec";
  WriteRecording(SmallRecording(), folder, "base: {xyz: [1, 2, 3]}\n");
  EXPECT_EQ(ReadText(folder + "/truth.yaml"), "base: {xyz: [1, 2, 3]}\n");
}

TEST(ReadRecording, MetresAndDegreesAreConvertedToMillimetresAndRadians) {
  const std::string folder = testing::TempDir("recording/units") + "/rec";
  testing::WriteText(folder + "/recording.yaml",
                     "format: cellmetry-recording/1\n"
                     "units: {length: m, angle: deg}\n"
                     "robots: {ur3: {joints: 6}}\n"
                     "cameras: [cam1]\n"
                     "targets: {tool: {on: ur3}, world: {on: world}}\n");
  testing::WriteText(folder + "/samples.csv",
                     "sample,robot,pose,q1,q2,q3,q4,q5,q6\n"
                     "0,ur3,0,90,-180,45,0,360,1\n");
  testing::WriteText(folder + "/observations.csv",
                     "sample,camera,target,x,y,z,rx,ry,rz\n"
                     "0,cam1,tool,0.5,-0.25,1.2,180,0,-90\n"
                     "0,cam1,world,1,2,3,,,\n");
  const Recording r = ReadRecording(folder);
  ASSERT_EQ(r.samples.size(), 1u);
  const std::vector<double> expected_q = {M_PI / 2, -M_PI, M_PI / 4, 0, 2 * M_PI, M_PI / 180};
  ASSERT_EQ(r.samples[0].q.size(), expected_q.size());
  for (size_t j = 0; j < expected_q.size(); ++j) {
    EXPECT_NEAR(r.samples[0].q[j], expected_q[j], 1e-12);
  }
  ASSERT_EQ(r.observations.size(), 2u);
  EXPECT_TRUE(r.observations[0].position_mm.isApprox(Eigen::Vector3d(500, -250, 1200), 1e-12));
  ASSERT_TRUE(r.observations[0].rvec.has_value());
  EXPECT_TRUE(r.observations[0].rvec->isApprox(Eigen::Vector3d(M_PI, 0, -M_PI / 2), 1e-12));
  EXPECT_TRUE(r.observations[1].position_mm.isApprox(Eigen::Vector3d(1000, 2000, 3000), 1e-12));
  EXPECT_FALSE(r.observations[1].rvec.has_value());

  // Written back in mm/rad with shortest round-trip digits: every double survives bit for bit
  // (simulated truth is compared at 1e-9, so 12 significant digits were not enough).
  const std::string copy = testing::TempDir("recording/units_copy") + "/rec";
  WriteRecording(r, copy);
  EXPECT_THAT(ReadText(copy + "/recording.yaml"), ::testing::HasSubstr("length: mm"));
  EXPECT_THAT(ReadText(copy + "/recording.yaml"), ::testing::HasSubstr("angle: rad"));
  const Recording again = ReadRecording(copy);
  for (size_t j = 0; j < expected_q.size(); ++j) {
    EXPECT_EQ(again.samples[0].q[j], r.samples[0].q[j]) << "q" << j + 1;
  }
  EXPECT_EQ(again.observations[0].position_mm, r.observations[0].position_mm);
  EXPECT_EQ(*again.observations[0].rvec, *r.observations[0].rvec);
}

TEST(WriteRecording, ReplacesAnExistingFolderAndLeavesNoStagingFolder) {
  const std::string parent = testing::TempDir("recording/replace");
  const std::string folder = parent + "/rec";
  WriteRecording(SmallRecording(), folder);  // with images.csv, which the next one lacks

  Recording smaller = SmallRecording();
  smaller.samples.resize(1);
  smaller.observations.resize(1);
  smaller.images.clear();
  WriteRecording(smaller, folder);

  const Recording read = ReadRecording(folder);
  EXPECT_EQ(read.samples.size(), 1u);
  EXPECT_EQ(read.observations.size(), 1u);
  EXPECT_TRUE(read.images.empty());
  EXPECT_FALSE(fs::exists(folder + "/images.csv"));
  std::vector<std::string> entries;
  for (const auto& entry : fs::directory_iterator(parent)) {
    entries.push_back(entry.path().filename().string());
  }
  std::sort(entries.begin(), entries.end());
  // The replaced recording stays recoverable beside it (atomic_file.h), one generation deep.
  EXPECT_EQ(entries, (std::vector<std::string>{"rec", "rec.previous"}));
  EXPECT_TRUE(fs::exists(folder + ".previous/images.csv"));
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
    EXPECT_EQ(name.find(".partial"), std::string::npos) << name;
  }
}

}  // namespace
}  // namespace cellmetry
