// Every `cellmetry` command quoted in README.md, docs/*.md and the comments of configs/ works as
// quoted: run in a copy of configs/ and tests/data/, in an order where each command's inputs
// exist (simulations and imports first, results before their exports). The long kinds
// (diagnose, plan, compare) run with `--check`: every input loaded and checked, the work not
// done; a command reading what only such a command would write is listed as not run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "support/test_support.h"

namespace cellmetry {
namespace {

namespace fs = std::filesystem;

struct QuotedCommand {
  std::string where;  // file:line
  std::string text;   // "run configs/jobs/x.yaml -o ..." (after `cellmetry `)
  std::string kind;   // the subcommand
};

const std::vector<std::string>& KindsInOrder() {
  static const std::vector<std::string> kinds = {
      "simulate", "import",   "calibrate-camera", "detect",     "run",     "home",   "diagnose",
      "plan",     "evaluate", "export",           "compensate", "compare", "plugins"};
  return kinds;
}

bool IsLong(const std::string& kind) {
  return kind == "diagnose" || kind == "plan" || kind == "compare";
}

std::vector<std::string> Tokens(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  return tokens;
}

// A quoted form (JOB.yaml, RESULT, <name>, [-n N], IMAGE...) rather than a command to run; or a
// mention of a command in prose, without the file it works on.
bool IsRunnable(const QuotedCommand& c) {
  static const std::regex placeholder("^[A-Z][A-Z_0-9]*(\\.[a-z]+)?\\.*$");
  const auto tokens = Tokens(c.text);
  bool names_a_file = c.kind == "plugins";
  for (const auto& t : tokens) {
    if (std::regex_match(t, placeholder) || t.find('<') != std::string::npos ||
        t.find('[') != std::string::npos || t.find("...") != std::string::npos) {
      return false;
    }
    const bool yaml = t.size() > 5 && t.compare(t.size() - 5, 5, ".yaml") == 0;
    if (t.find('/') != std::string::npos || yaml) names_a_file = true;
  }
  return names_a_file;
}

// The command starting at `at` in `line` (just after "cellmetry "), up to a closing backtick, a
// table bar or a comment; continued on the next lines after a trailing backslash or while an
// inline code span stays open.
std::string CommandAt(const std::vector<std::string>& lines, size_t index, size_t at,
                      bool in_code_span) {
  std::string text;
  for (size_t i = index; i < lines.size(); ++i, at = 0) {
    const std::string rest = lines[i].substr(at);
    size_t end = rest.find_first_of("`|");
    const size_t comment = rest.find(" #");
    if (comment != std::string::npos && (end == std::string::npos || comment < end)) end = comment;
    std::string part = rest.substr(0, end);
    const bool continued = !part.empty() && part.find_last_not_of(' ') != std::string::npos &&
                           part[part.find_last_not_of(' ')] == '\\';
    if (continued) part = part.substr(0, part.find_last_not_of(' '));
    text += " " + part;
    const bool span_open = in_code_span && end == std::string::npos;
    if (!continued && !span_open) break;
  }
  return text;
}

std::vector<QuotedCommand> QuotedIn(const fs::path& file, const std::string& relative) {
  static const std::regex start(
      "(^|[\\s`/])cellmetry ((--[a-z]+ )*)(run|simulate|detect|diagnose|evaluate|home|compare|"
      "export|compensate|import|calibrate-camera|plugins|plan)\\b");
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  const bool yaml = file.extension() == ".yaml";
  std::vector<QuotedCommand> found;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (yaml && lines[i].find('#') == std::string::npos) continue;
    for (std::sregex_iterator m(lines[i].begin(), lines[i].end(), start), end; m != end; ++m) {
      const size_t at = m->position(0) + m->length(1) + std::string("cellmetry ").size();
      const bool in_code_span = m->str(1) == "`";
      QuotedCommand c{relative + ":" + std::to_string(i + 1), CommandAt(lines, i, at, in_code_span),
                      m->str(4)};
      std::string normal;  // one space between words, as a shell reads it
      for (const auto& t : Tokens(c.text)) normal += (normal.empty() ? "" : " ") + t;
      c.text = normal;
      // Global flags quoted before the subcommand stay with it; --quiet is added anyway.
      if (IsRunnable(c)) found.push_back(c);
    }
  }
  return found;
}

std::vector<QuotedCommand> EveryQuotedCommand() {
  const fs::path root = testing::Source("");
  std::vector<fs::path> files = {root / "README.md"};
  for (const auto& e : fs::directory_iterator(root / "docs")) {
    if (e.path().extension() == ".md") files.push_back(e.path());
  }
  for (const auto& e : fs::recursive_directory_iterator(root / "configs")) {
    if (e.path().extension() == ".yaml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<QuotedCommand> all;
  std::set<std::string> seen;
  for (const auto& file : files) {
    for (auto& c : QuotedIn(file, fs::relative(file, root).string())) {
      if (seen.insert(c.text).second) all.push_back(c);
    }
  }
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    const auto& order = KindsInOrder();
    return std::find(order.begin(), order.end(), a.kind) <
           std::find(order.begin(), order.end(), b.kind);
  });
  return all;
}

testing::CommandResult Shell(const std::string& folder, const std::string& command) {
  const std::string line = "cd '" + folder + "' && " + command + " 2>&1";
  testing::CommandResult result;
  FILE* pipe = popen(line.c_str(), "r");
  char buffer[4096];
  while (pipe != nullptr && std::fgets(buffer, sizeof buffer, pipe) != nullptr) {
    result.output += buffer;
  }
  const int status = pipe == nullptr ? -1 : pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// The extraction itself: a command on one line, one continued after a backslash, one whose
// inline code span runs onto the next line, a config's comment, and no template or mention.
TEST(DocumentedCommands, QuotedCommandsAreFoundWhole) {
  std::map<std::string, std::string> by_text;
  for (const auto& c : EveryQuotedCommand()) by_text[c.text] = c.where;
  auto has = [&](const std::string& prefix) {
    return std::any_of(by_text.begin(), by_text.end(),
                       [&](const auto& entry) { return entry.first.rfind(prefix, 0) == 0; });
  };
  EXPECT_TRUE(has("run configs/jobs/vsb_exp_a.yaml"));
  EXPECT_TRUE(
      has("compensate results/staubli_tx90l_diagnose/diagnosis/final_fit/held_out_setup "
          "results/staubli_tx90l_diagnose/diagnosis/final_fit/held_out_setup/"
          "targets_tmac.csv -o results/tx90l_commands.csv"));
  EXPECT_TRUE(has("plan configs/jobs/staubli_tx90l_diagnose.yaml -n 20 --effect"));
  EXPECT_TRUE(has("simulate configs/simulations/ur3_eye_to_hand.yaml -o results/ur3_eye_to_hand"));
  for (const auto& [text, where] : by_text) {
    EXPECT_EQ(text.find("JOB.yaml"), std::string::npos) << where << ": " << text;
    EXPECT_NE(text, "run") << where;
  }
}

TEST(DocumentedCommands, EveryQuotedCommandWorksAsQuoted) {
  const std::vector<QuotedCommand> commands = EveryQuotedCommand();
  ASSERT_GT(commands.size(), 50u);  // the extraction still finds the docs' commands
  const std::string root = testing::TempDirForThisTest("documented_commands");
  fs::copy(testing::Source("configs"), root + "/configs", fs::copy_options::recursive);
  fs::create_directories(root + "/tests");
  fs::copy(testing::Source("tests/data"), root + "/tests/data", fs::copy_options::recursive);
  fs::create_directories(root + "/docs");
  fs::copy(testing::Source("docs/physics.md"), root + "/docs/physics.md");
  std::vector<std::string> would_write;  // outputs of commands run with --check only
  int ran = 0, checked = 0;
  std::string not_run;
  for (const QuotedCommand& c : commands) {
    const bool reads_unwritten = std::any_of(
        would_write.begin(), would_write.end(),
        [&](const std::string& folder) { return c.text.find(" " + folder) != std::string::npos; });
    if (reads_unwritten) {
      not_run += "\n  " + c.where + ": cellmetry " + c.text;
      continue;
    }
    const bool check = IsLong(c.kind);
    const auto r = Shell(
        root, std::string(CELLMETRY_BINARY) + " --quiet" + (check ? " --check " : " ") + c.text);
    EXPECT_EQ(r.exit_code, 0) << c.where << ": cellmetry " << c.text << "\n" << r.output;
    const size_t at = r.output.find("would write ");
    if (check && at != std::string::npos) {
      std::string folder = r.output.substr(at + 12);
      folder = folder.substr(0, folder.find('\n'));
      would_write.push_back(
          fs::relative(fs::weakly_canonical(fs::path(root) / folder), root).string());
    }
    (check ? checked : ran) += 1;
  }
  std::printf(
      "%d commands run, %d checked (--check), not run (they read what a checked command "
      "would write):%s\n",
      ran, checked, not_run.empty() ? " none" : not_run.c_str());
}

}  // namespace
}  // namespace cellmetry
