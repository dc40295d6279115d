// ConfigNode: every YAML complaint names the file, line, column and key path, and says what to do.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cellmetry/formats/config_node.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

// Writes `text` to a fresh file and loads it.
ConfigNode LoadText(const std::string& test, const std::string& text, std::string* path = nullptr) {
  const std::string file = testing::TempDir("config/" + test) + "/job.yaml";
  testing::WriteText(file, text);
  if (path) *path = file;
  return ConfigNode::LoadFile(file);
}

using testing::CatchInputError;

TEST(ConfigNode, UnknownKeyNamesFileLineColumnAndKeyPath) {
  std::string path;
  const ConfigNode root = LoadText("unknown_key",
                                   "robots:\n"
                                   "  ur3:\n"
                                   "    base:\n"
                                   "      fre: all\n",
                                   &path);
  const ConfigNode base = root["robots"]["ur3"]["base"];
  const InputError e = CatchInputError([&] { base.ExpectKeys({"free", "start"}); });
  EXPECT_EQ(e.where().file, path);
  EXPECT_EQ(e.where().line, 4);
  EXPECT_EQ(e.where().column, 7);
  EXPECT_THAT(e.message(), HasSubstr("robots.ur3.base.fre"));
  EXPECT_THAT(e.message(), HasSubstr("unknown key"));
  EXPECT_THAT(std::string(e.what()), StartsWith(path + ":4:7: error: robots.ur3.base.fre"));
}

TEST(ConfigNode, UnknownKeySuggestsTheNearMiss) {
  const ConfigNode base = LoadText("near_miss", "fre: all\n");
  const InputError e = CatchInputError([&] { base.ExpectKeys({"free", "start"}); });
  EXPECT_THAT(e.hint(), HasSubstr("Did you mean 'free'?"));
  EXPECT_THAT(e.hint(), HasSubstr("Known keys: free, start"));
}

TEST(ConfigNode, UnknownKeyFarFromAnyKnownKeyListsThemWithoutAGuess) {
  const ConfigNode base = LoadText("far_miss", "colour: blue\n");
  const InputError e = CatchInputError([&] { base.ExpectKeys({"free", "start"}); });
  EXPECT_THAT(e.hint(), Not(HasSubstr("Did you mean")));
  EXPECT_THAT(e.hint(), HasSubstr("Known keys: free, start"));
}

TEST(ConfigNode, KnownKeysPass) {
  const ConfigNode base = LoadText("known_keys", "free: all\nstart: {xyz: [1, 2, 3]}\n");
  EXPECT_NO_THROW(base.ExpectKeys({"free", "start"}));
  EXPECT_EQ(base.Keys(), (std::vector<std::string>{"free", "start"}));
}

TEST(ConfigNode, TextWhereANumberIsExpectedNamesTheKeyPath) {
  const ConfigNode root = LoadText("wrong_type", "validation:\n  folds: many\n  sigma: wide\n");
  const InputError as_int = CatchInputError([&] { root["validation"]["folds"].AsInt(); });
  EXPECT_THAT(as_int.message(), HasSubstr("validation.folds"));
  EXPECT_THAT(as_int.message(), HasSubstr("'many'"));
  EXPECT_EQ(as_int.where().line, 2);
  EXPECT_EQ(as_int.where().column, 10);
  EXPECT_FALSE(as_int.hint().empty());

  const InputError as_double = CatchInputError([&] { root["validation"].GetDouble("sigma", 1.0); });
  EXPECT_THAT(as_double.message(), HasSubstr("validation.sigma"));
  EXPECT_THAT(as_double.message(), HasSubstr("expected a number"));
  EXPECT_EQ(as_double.where().line, 3);
}

TEST(ConfigNode, AListWhereANumberIsExpectedIsRejected) {
  const ConfigNode root = LoadText("list_for_number", "scale: [1, 2]\n");
  const InputError e = CatchInputError([&] { root["scale"].AsDouble(); });
  EXPECT_THAT(e.message(), HasSubstr("scale: expected a number, got a list"));
}

TEST(ConfigNode, NanAndInfinityAreRejected) {
  const ConfigNode root = LoadText("not_finite", "a: .nan\nb: .inf\nc: -.inf\nd: [1, .nan, 3]\n");
  for (const std::string key : {"a", "b", "c"}) {
    SCOPED_TRACE(key);
    const InputError e = CatchInputError([&] { root[key].AsDouble(); });
    EXPECT_THAT(e.message(), HasSubstr(key + ": expected a finite number"));
  }
  const InputError in_list = CatchInputError([&] { root["d"].AsDoubles(3); });
  EXPECT_THAT(in_list.message(), HasSubstr("d[1]: expected a finite number"));
}

TEST(ConfigNode, NumbersAreRead) {
  const ConfigNode root = LoadText("numbers", "a: -2.5e3\nb: 7\nxyz: [1, 2.5, -3]\n");
  EXPECT_EQ(root["a"].AsDouble(), -2500.0);
  EXPECT_EQ(root["b"].AsInt(), 7);
  EXPECT_EQ(root["xyz"].AsDoubles(3), (std::vector<double>{1, 2.5, -3}));
  EXPECT_EQ(root.GetDouble("absent", 4.5), 4.5);
}

TEST(ConfigNode, ListOfTheWrongLengthIsRejected) {
  const ConfigNode root = LoadText("wrong_length", "xyz: [1, 2]\n");
  const InputError e = CatchInputError([&] { root["xyz"].AsDoubles(3); });
  EXPECT_THAT(e.message(), HasSubstr("xyz: expected a list of 3 numbers, got 2"));
}

TEST(ConfigNode, MissingKeyIsNamedWithItsParentPath) {
  const ConfigNode root = LoadText("missing_key", "solver:\n  iterations: 3\n");
  const InputError e = CatchInputError([&] { root["solver"]["type"]; });
  EXPECT_THAT(e.message(), HasSubstr("solver: missing key 'type'"));
  EXPECT_EQ(e.where().line, 2);
}

TEST(ConfigNode, MissingFileIsAnInputErrorNamingThePath) {
  const std::string path = testing::TempDir("config/missing_file") + "/no_such.yaml";
  const InputError e = CatchInputError([&] { ConfigNode::LoadFile(path); });
  EXPECT_EQ(e.where().file, path);
  EXPECT_THAT(std::string(e.what()), StartsWith(path + ": error: cannot open file"));
  EXPECT_FALSE(e.hint().empty());
}

TEST(ConfigNode, YamlSyntaxErrorIsLocated) {
  std::string path;
  const InputError e = CatchInputError([&] {
    LoadText("syntax",
             "job: workcell\n"
             "solver:\n"
             "  type: ceres_lm\n"
             "robots: ur3: ur5\n",
             &path);
  });
  EXPECT_EQ(e.where().file, path);
  EXPECT_EQ(e.where().line, 4);
  EXPECT_GT(e.where().column, 0);
  EXPECT_THAT(e.message(), HasSubstr("YAML syntax"));
  EXPECT_FALSE(e.hint().empty());
}

TEST(ConfigNode, ResolvePathIsRelativeToTheFilesFolder) {
  std::string path;
  const ConfigNode root =
      LoadText("resolve", "robots:\n  ur3:\n    model: ../robots/ur3_vsb2020.yaml\n", &path);
  const std::string folder = std::filesystem::path(path).parent_path().string();
  const std::string parent = std::filesystem::path(folder).parent_path().string();
  const ConfigNode ur3 = root["robots"]["ur3"];
  EXPECT_EQ(ur3.ResolvePath(ur3["model"].AsString()), parent + "/robots/ur3_vsb2020.yaml");
  EXPECT_EQ(root.ResolvePath("data/rec"), folder + "/data/rec");
  EXPECT_EQ(root.ResolvePath("/abs/./rec"), "/abs/rec");
}

TEST(ConfigNode, ResolvePathOfTextWithoutAFileIsLeftRelative) {
  const ConfigNode root = ConfigNode::LoadString("a: 1\n", "");
  EXPECT_EQ(root.ResolvePath("data/./rec"), "data/rec");
}

TEST(ConfigNode, LoadStringNamesItsOriginInErrors) {
  const ConfigNode root = ConfigNode::LoadString("folds: many\n", "<command line>");
  const InputError e = CatchInputError([&] { root["folds"].AsInt(); });
  EXPECT_THAT(std::string(e.what()), StartsWith("<command line>:1:8: error: folds:"));
}

TEST(NearestWord, FindsTheClosestCandidate) {
  EXPECT_EQ(NearestWord("fre", {"free", "start"}), "free");
  EXPECT_EQ(NearestWord("solvr", {"job", "robots", "solver", "validation"}), "solver");
  EXPECT_EQ(NearestWord("ceres_lmm", {"ceres_lm", "jacobian_pinv", "nlopt"}), "ceres_lm");
  EXPECT_EQ(NearestWord("serial_mdhh", {"serial_mdh"}), "serial_mdh");
  EXPECT_EQ(NearestWord("free", {"free", "frees"}), "free");
}

TEST(NearestWord, SuggestsNothingWhenNothingIsClose) {
  EXPECT_EQ(NearestWord("colour", {"free", "start"}), "");
  EXPECT_EQ(NearestWord("x", {}), "");
}

}  // namespace
}  // namespace cellmetry
