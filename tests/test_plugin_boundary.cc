// The core never knows a plugin by name: no code under core/ writes a registered plugin's
// `type:` (a detector, robot model, solver or effect) into the YAML it builds. What a plugin
// offers (an effect's diagnosis candidates included) comes from the plugin, through the registry.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.h"

namespace cellmetry {
namespace {

// `text` less its `//` comments (a comment may show a user's YAML).
std::string WithoutComments(const std::string& text) {
  std::string out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const size_t comment = line.find("//");
    out += (comment == std::string::npos ? line : line.substr(0, comment)) + "\n";
  }
  return out;
}

std::vector<std::string> PluginTypes() {
  std::vector<std::string> types;
  for (PluginKind kind :
       {PluginKind::kDetector, PluginKind::kRobotModel, PluginKind::kSolver, PluginKind::kEffect}) {
    for (const std::string& name : testing::Plugins().Names(kind)) types.push_back(name);
  }
  return types;
}

// "file: type: <name>" for each place under `folder` whose code writes a plugin's type.
std::vector<std::string> PluginTypesWritten(const std::string& folder) {
  std::vector<std::string> found;
  const std::vector<std::string> types = PluginTypes();
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".cc" && ext != ".h") continue;
    const std::string code = WithoutComments(testing::ReadText(entry.path().string()));
    for (const std::string& type : types) {
      const std::regex written("type:\\s*" + type + "\\b");
      if (std::regex_search(code, written)) {
        found.push_back(entry.path().string() + ": type: " + type);
      }
    }
  }
  return found;
}

TEST(PluginBoundary, TheCoreWritesNoPluginsType) {
  ASSERT_GE(PluginTypes().size(), 20u);  // the bundled plugins were loaded
  const std::vector<std::string> found = PluginTypesWritten(testing::Source("core"));
  std::string list;
  for (const auto& f : found) list += f + "\n";
  EXPECT_TRUE(found.empty()) << list;
}

// The check finds what it looks for: the effect library writes its own types.
TEST(PluginBoundary, TheCheckFindsTheEffectLibrarysOwnTypes) {
  EXPECT_FALSE(PluginTypesWritten(testing::Source("plugins/effects")).empty());
}

}  // namespace
}  // namespace cellmetry
