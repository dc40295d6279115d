// docs/architecture.md names the core's layers as core/CMakeLists.txt builds them: the layers
// declared there with cellmetry_add_layer(<name> ...) and the rows "| `<name>` |" of the table
// under the heading "## Layers" are the same set.
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "support/test_support.h"

namespace cellmetry {
namespace {

std::string Joined(const std::set<std::string>& names) {
  std::string text;
  for (const auto& n : names) text += (text.empty() ? "" : ", ") + n;
  return "{" + text + "}";
}

// Every `cellmetry_add_layer(<name>` at the start of a line (the function's own definition,
// `function(cellmetry_add_layer name)`, does not start a line with the call).
std::set<std::string> LayersInCMake(const std::string& cmake) {
  static const std::regex call("^cellmetry_add_layer\\(\\s*([a-z_]+)");
  std::set<std::string> names;
  std::istringstream in(cmake);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, call)) names.insert(m[1]);
  }
  return names;
}

// The first cells "| `<name>` |" of the table rows between "## Layers" and the next heading of
// the same or a higher level.
std::set<std::string> LayersInDoc(const std::string& doc, bool* found_heading) {
  static const std::regex row("^\\|\\s*`([a-z_]+)`\\s*\\|");
  std::set<std::string> names;
  std::istringstream in(doc);
  bool inside = false;
  bool table_seen = false;
  *found_heading = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## ", 0) == 0 || line.rfind("# ", 0) == 0) {
      inside = line == "## Layers";
      if (inside) *found_heading = true;
      continue;
    }
    if (!inside) continue;
    std::smatch m;
    if (std::regex_search(line, m, row)) {
      names.insert(m[1]);
      table_seen = true;
    } else if (table_seen && line.rfind("|", 0) != 0) {
      break;  // the layer table ended: later tables in the section are not layers
    }
  }
  return names;
}

TEST(ArchitectureDoc, LayerTableMatchesCoreCMakeLists) {
  const std::set<std::string> cmake =
      LayersInCMake(testing::ReadText(testing::Source("core/CMakeLists.txt")));
  bool heading = false;
  const std::set<std::string> doc =
      LayersInDoc(testing::ReadText(testing::Source("docs/architecture.md")), &heading);
  ASSERT_TRUE(heading) << "docs/architecture.md has no heading \"## Layers\"";
  ASSERT_FALSE(cmake.empty()) << "no cellmetry_add_layer(...) found in core/CMakeLists.txt";
  EXPECT_EQ(doc, cmake) << "docs/architecture.md, table under \"## Layers\": " << Joined(doc)
                        << "\ncore/CMakeLists.txt, cellmetry_add_layer: " << Joined(cmake);
}

// The extraction itself, on text where a layer is missing and one is extra.
TEST(ArchitectureDoc, ExtractionFindsTheLayerTableOnly) {
  const std::string cmake =
      "function(cellmetry_add_layer name)\nendfunction()\n"
      "cellmetry_add_layer(basics\n  SOURCES a.cc)\ncellmetry_add_layer(cell SOURCES b.cc)\n";
  EXPECT_EQ(LayersInCMake(cmake), (std::set<std::string>{"basics", "cell"}));
  const std::string doc =
      "# A\n\n## Layers\n\n| layer | owns |\n|---|---|\n| `basics` | x |\n| `old` | y |\n\n"
      "| part | owns |\n|---|---|\n| `experiments` | z |\n\n## Rules\n\n| `rules` | w |\n";
  bool heading = false;
  EXPECT_EQ(LayersInDoc(doc, &heading), (std::set<std::string>{"basics", "old"}));
  EXPECT_TRUE(heading);
}

}  // namespace
}  // namespace cellmetry
