// The input contract the fuzz harnesses (fuzz/) check, replayed here on every build: each input a
// harness or a review found crashing, throwing something other than InputError, or loading what
// no run could have written, and what it must give now. New findings become rows of these tables.
// docs/reliability.md lists them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cellmetry/basics/error.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/imaging/detection.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

// A detection log (detections.jsonl) and what reading it gives: an InputError at `location`, or
// `loaded` detections and the log afterwards.
struct LogCase {
  std::string name;
  std::string log;
  std::string location;  // ":LINE:" or ":LINE:COLUMN:" of the error; empty when it loads
  std::string message;
  int loaded = 0;
  std::string log_after;  // the file after reading, when it loads
};

class DetectionLog : public ::testing::TestWithParam<LogCase> {};

const std::string kGood =
    R"({"camera":"cam1","failure":"","keypoints":[[0,100.5,200.25,0.01,0.0,0.01]],"path":"images/0.png","sample":0,"target":"tool","time_ms":3.25,"view":"mono"})";

std::string With(const std::string& from, const std::string& to) {
  std::string line = kGood;
  const size_t at = line.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return line.replace(at, from.size(), to);
}

LogCase Loads(std::string name, std::string log, int loaded, std::string after) {
  return {std::move(name), std::move(log), "", "", loaded, std::move(after)};
}

LogCase Refused(std::string name, std::string log, std::string location, std::string message) {
  return {std::move(name), std::move(log), std::move(location), std::move(message), 0, ""};
}

TEST_P(DetectionLog, LoadsOrIsRefusedAtItsLine) {
  const LogCase& c = GetParam();
  const std::string path = testing::TempDirForThisTest("input_contract") + "/detections.jsonl";
  testing::WriteText(path, c.log);
  if (c.location.empty()) {
    EXPECT_EQ(static_cast<int>(ReadDetectionLog(path).size()), c.loaded);
    EXPECT_EQ(testing::ReadText(path), c.log_after);
    return;
  }
  try {
    ReadDetectionLog(path);
    ADD_FAILURE() << "loaded";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("detections.jsonl" + c.location));
    EXPECT_THAT(e.what(), HasSubstr(c.message));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Rows, DetectionLog,
    ::testing::Values(
        Loads("TwoGoodLines", kGood + "\n" + kGood + "\n", 2, kGood + "\n" + kGood + "\n"),
        Loads("TornLastLineIsDropped", kGood + "\n" + kGood.substr(0, 40), 1, kGood + "\n"),
        // A complete last line without its newline: the next run's append must not join it.
        Loads("LastLineWithoutNewlineGetsOne", kGood, 1, kGood + "\n"),
        Loads("BlankLinesAreSkipped", "\n" + kGood + "\n\n", 1, "\n" + kGood + "\n\n"),
        // Was: read as a torn last line, and the log truncated there, losing every line after it.
        Refused("DamagedLineBeforeTheLastIsRefusedNotTruncated",
                kGood + "\n{\"sample\": 5, \"cam\n" + kGood + "\n", ":2:", "is not JSON"),
        // Was: static_cast<int>(1e30), undefined behaviour (UBSan: float-cast-overflow).
        Refused("FloatSampleId", With("\"sample\":0", "\"sample\":1e30") + "\n" + kGood + "\n",
                ":1:", "'sample' is not a whole number"),
        Refused("NegativeSampleId", With("\"sample\":0", "\"sample\":-1") + "\n" + kGood + "\n",
                ":1:", "'sample' is out of range"),
        Refused("SampleIdBeyondInt",
                With("\"sample\":0", "\"sample\":4294967296") + "\n" + kGood + "\n",
                ":1:", "out of range"),
        Refused("KeypointIdAsFloat", With("[[0,", "[[0.5,") + "\n" + kGood + "\n",
                ":1:", "a keypoint id is not a whole number"),
        Refused("KeypointWithFiveNumbers", With(",0.01]]", "]]") + "\n" + kGood + "\n",
                ":1:", "a keypoint is not [id, x, y"),
        Refused("NegativePixelVariance",
                With("0.01,0.0,0.01", "-0.01,0.0,0.01") + "\n" + kGood + "\n",
                ":1:", "not positive semi-definite"),
        Refused("CovarianceNotPositiveSemiDefinite",
                With("0.01,0.0,0.01", "0.01,0.5,0.01") + "\n" + kGood + "\n",
                ":1:", "not positive semi-definite"),
        Refused("PixelAsText", With("100.5", "\"x\"") + "\n" + kGood + "\n",
                ":1:", "a keypoint's x is not a number"),
        Refused("CameraAsNumber", With("\"cam1\"", "7") + "\n" + kGood + "\n",
                ":1:", "'camera' is not a string"),
        Refused("MissingTarget", With("\"target\":\"tool\",", "") + "\n" + kGood + "\n",
                ":1:", "no 'target'"),
        Refused("AListNotAnObject", "[1,2]\n" + kGood + "\n", ":1:", "not a JSON object")),
    [](const ::testing::TestParamInfo<LogCase>& info) { return info.param.name; });

// YAML text (a job, a robot config, recording.yaml: all read by ConfigNode) and where it must be
// refused.
struct YamlCase {
  std::string name;
  std::string text;
  int line;
  std::string message;
};

class YamlText : public ::testing::TestWithParam<YamlCase> {};

TEST_P(YamlText, IsRefusedAtItsLine) {
  const YamlCase& c = GetParam();
  try {
    const ConfigNode root = ConfigNode::LoadString(c.text, "robot.yaml");
    root.Keys();
    root.ExpectKeys({"type"});
    ADD_FAILURE() << "loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "robot.yaml");
    EXPECT_EQ(e.where().line, c.line);
    EXPECT_THAT(e.message(), HasSubstr(c.message));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Rows, YamlText,
    ::testing::Values(
        // fuzz_robot_config, 8 s: yaml-cpp's TypedBadConversion escaped from ConfigNode::Keys and
        // ExpectKeys (exit 1, "internal error") for a list as a key.
        YamlCase{"AListAsAKey", "type: delta\n? - {R: 150, r: 40}\n: 3\n", 2,
                 "a key must be a word, not a list"},
        YamlCase{"AMapAsAKey", "type: delta\narms:\n  ? {R: 150}\n  : 3\n", 3,
                 "a key must be a word, not a map"}),
    [](const ::testing::TestParamInfo<YamlCase>& info) { return info.param.name; });

}  // namespace
}  // namespace cellmetry
