// ConfigNode (config_node.h): YAML nodes that know their file, line and key path, so that every
// complaint names where it is, with a "did you mean" for a misspelt key.
#include "cellmetry/formats/config_node.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <string_view>

#include "cellmetry/basics/text.h"
#include "cellmetry/formats/input_file.h"
#include "cellmetry/formats/quoted_text.h"

namespace cellmetry {
namespace {

size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string Describe(const YAML::Node& node) {
  if (!node || node.IsNull()) return "nothing";
  if (node.IsMap()) return "a map";
  if (node.IsSequence()) return "a list";
  // A whole CSV given as a YAML file is one scalar: quoted in full it made a line of kilobytes.
  const std::string& text = node.Scalar();
  if (text.size() > 60)
    return "'" + text.substr(0, 40) + "...' (" + std::to_string(text.size()) + " characters)";
  return "'" + text + "'";
}

}  // namespace

std::string NearestWord(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& candidate : candidates) {
    const size_t d = EditDistance(word, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  return best;
}

ConfigNode ConfigNode::LoadFile(const std::string& path) {
  // A folder opens as a stream on Linux and reads as nothing: "expected a map of keys, got
  // nothing" left the user guessing.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError({path, 0, 0}, "is a folder, not a YAML file",
                     "Give the path of the YAML file itself");
  }
  return LoadString(
      ReadRegularFile(path, kMaxYamlBytes,
                      "Check the path (relative paths in a job are relative to the job file)"),
      path);
}

namespace {

// A YAML alias (*name) is the node its anchor (&name) made, not a copy: a file of a few lines
// can name one node 10^9 times through nested aliases, and every reader that walks the tree
// walks each time. The walk below, the first after parsing, counts the nodes it visits with
// aliases expanded and stops at kMaxYamlNodes: the largest bundled file (the ten-robot
// simulation) has about 400, a bomb of 9 levels 387 million.
constexpr size_t kMaxYamlNodes = 100000;

struct NodeBudget {
  std::string origin;
  size_t visited = 0;

  void Visit(const YAML::Node& node) {
    if (++visited <= kMaxYamlNodes) return;
    const YAML::Mark mark = node.Mark();
    throw InputError(
        {origin, mark.is_null() ? 0 : mark.line + 1, mark.is_null() ? 0 : mark.column + 1},
        "more than " + std::to_string(kMaxYamlNodes) +
            " values once anchors (&) and aliases (*) are expanded",
        "Write the values out, or use fewer aliases: a cellmetry file holds a "
        "few hundred values");
  }
};

// Every key a word (a reader takes keys with as<std::string>, which throws on a list or a map).
// yaml-cpp keeps the second of two equal keys in a map without a word (and a reader takes the
// first): a job that says `folds: 5` twice means one of them by mistake.
// Nesting deeper than this is refused: a cellmetry file nests a few levels, and an alias inside
// its own anchor (`a: &a [*a]`) makes a node that contains itself, which no walk would leave.
constexpr int kMaxYamlDepth = 64;

void RefuseDuplicateKeys(const YAML::Node& node, NodeBudget& budget, int depth = 0) {
  budget.Visit(node);
  if (depth > kMaxYamlDepth) {
    const YAML::Mark mark = node.Mark();
    throw InputError(
        {budget.origin, mark.is_null() ? 0 : mark.line + 1, mark.is_null() ? 0 : mark.column + 1},
        "values nested more than " + std::to_string(kMaxYamlDepth) +
            " deep (or an alias (*) inside its own anchor (&))",
        "Write the values out: a cellmetry file nests a few levels");
  }
  if (node.IsSequence()) {
    for (const auto& element : node) RefuseDuplicateKeys(element, budget, depth + 1);
  }
  if (!node.IsMap()) return;
  const std::string& origin = budget.origin;
  std::set<std::string> seen;
  for (const auto& entry : node) {
    // YAML allows a list or a map as a key (`? [a, b]: 1`); no cellmetry file has one, and every
    // reader takes keys as words.
    if (entry.first.IsSequence() || entry.first.IsMap()) {
      const YAML::Mark mark = entry.first.Mark();
      throw InputError(
          {origin, mark.line + 1, mark.column + 1},
          "a key must be a word, not a " + std::string(entry.first.IsSequence() ? "list" : "map"),
          "Write 'name: value'; a '?' at the start of a line makes what follows a key");
    }
    if (entry.first.IsScalar() && !seen.insert(entry.first.Scalar()).second) {
      const YAML::Mark mark = entry.first.Mark();
      throw InputError({origin, mark.line + 1, mark.column + 1},
                       "key '" + entry.first.Scalar() + "' appears twice in this map",
                       "Keep one of them");
    }
    RefuseDuplicateKeys(entry.second, budget, depth + 1);
  }
}

// The 1-based line of a second document's marker in `text` (0 when there is none): a '---'
// at the start of a line after content, or content after a '...' line. YAML::Load reads the
// first document only, so what follows would be read by nothing. A scan of the lines, not a
// parse of the rest: parsing every document (YAML::LoadAll) grew memory without bound on
// fuzzed input. A '---' at the start of a line cannot be inside a scalar: YAML forbids it there.
int SecondDocumentLine(const std::string& text) {
  bool content = false, ended = false;
  int line_number = 0;
  for (size_t begin = 0; begin < text.size();) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + begin, end - begin);
    begin = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const auto marker = [&](std::string_view m) {
      return line.substr(0, 3) == m && (line.size() == 3 || line[3] == ' ' || line[3] == '\t');
    };
    const size_t first = line.find_first_not_of(" \t");
    const bool blank = first == std::string_view::npos || line[first] == '#';
    if (marker("---")) {
      if (content || ended) return line_number;
      content = line.find_first_not_of(" \t", 3) != std::string_view::npos &&
                line[line.find_first_not_of(" \t", 3)] != '#';
    } else if (marker("...")) {
      ended = true;
    } else if (!blank && line[0] != '%') {  // a %YAML directive belongs to the next document
      if (ended) return line_number;
      content = true;
    }
  }
  return 0;
}

}  // namespace

ConfigNode ConfigNode::LoadString(const std::string& text, const std::string& origin) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError({origin, e.mark.line + 1, e.mark.column + 1}, "YAML syntax: " + e.msg,
                     "Fix the YAML syntax (indentation, colons, brackets)");
  }
  if (const int line = SecondDocumentLine(text)) {
    throw InputError({origin, line, 1}, "a second YAML document in one file ('---' starts it)",
                     "cellmetry reads one document per file: remove the '---' and what follows, "
                     "or put it in a file of its own");
  }
  NodeBudget budget{origin};
  RefuseDuplicateKeys(root, budget);
  return ConfigNode(root, origin, "");
}

ConfigNode::ConfigNode(YAML::Node node, std::string file, std::string key_path)
    : node_(node), file_(std::move(file)), key_path_(std::move(key_path)) {}

SourceLocation ConfigNode::location() const {
  const YAML::Mark mark = node_ ? node_.Mark() : YAML::Mark::null_mark();
  if (mark.is_null()) return {file_, 0, 0};
  return {file_, mark.line + 1, mark.column + 1};
}

std::string ConfigNode::ChildPath(const std::string& key) const {
  return key_path_.empty() ? key : key_path_ + "." + key;
}

std::string ConfigNode::FlowText() const {
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << node_;
  return out.c_str();
}

SourceLocation ConfigNode::KeyLocation(const std::string& key) const {
  if (node_.IsMap()) {
    for (const auto& entry : node_) {
      if (entry.first.as<std::string>() != key) continue;
      const YAML::Mark mark = entry.first.Mark();
      if (!mark.is_null()) return {file_, mark.line + 1, mark.column + 1};
    }
  }
  return location();
}

InputError ConfigNode::Error(const std::string& what, const std::string& hint) const {
  // Readers quote a value whole ("unknown solver type '...'"). A path is quoted whole, as the
  // user must find it; a value longer than any path (PATH_MAX) is cut to 80 characters.
  constexpr size_t kLongestPath = 4096;
  const std::string said =
      node_ && node_.IsScalar() ? WithTextShortened(what, node_.Scalar(), kLongestPath) : what;
  return InputError(location(), (key_path_.empty() ? "" : key_path_ + ": ") + said, hint);
}

bool ConfigNode::Has(const std::string& key) const {
  return node_.IsMap() && node_[key] && !node_[key].IsNull();
}

ConfigNode ConfigNode::operator[](const std::string& key) const {
  ExpectMap();
  const YAML::Node child = node_[key];
  if (!child || child.IsNull()) {
    throw Error("missing key '" + key + "'", "Add '" + key + ":' here");
  }
  return ConfigNode(child, file_, ChildPath(key));
}

std::optional<ConfigNode> ConfigNode::Optional(const std::string& key) const {
  if (!Has(key)) return std::nullopt;
  return (*this)[key];
}

std::vector<std::string> ConfigNode::Keys() const {
  ExpectMap();
  std::vector<std::string> keys;
  for (const auto& entry : node_) keys.push_back(entry.first.as<std::string>());
  return keys;
}

std::vector<ConfigNode> ConfigNode::Elements() const {
  ExpectSequence();
  std::vector<ConfigNode> elements;
  for (size_t i = 0; i < node_.size(); ++i) {
    elements.emplace_back(node_[i], file_, key_path_ + "[" + std::to_string(i) + "]");
  }
  return elements;
}

void ConfigNode::ExpectMap() const {
  if (!node_.IsMap()) {
    throw Error("expected a map of keys, got " + Describe(node_),
                "Write 'key: value' lines here (docs/formats.md lists each file's keys)");
  }
}

void ConfigNode::ExpectSequence() const {
  if (!node_.IsSequence()) {
    throw Error("expected a list, got " + Describe(node_), "Write a list in brackets: [a, b, c]");
  }
}

void ConfigNode::ExpectKeys(const std::vector<std::string>& allowed) const {
  ExpectMap();
  for (const auto& entry : node_) {
    const std::string key = entry.first.as<std::string>();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    const std::string nearest = NearestWord(key, allowed);
    const YAML::Mark mark = entry.first.Mark();
    const std::string hint = nearest.empty()
                                 ? "Known keys: " + Join(allowed)
                                 : "Did you mean '" + nearest + "'? Known keys: " + Join(allowed);
    throw InputError({file_, mark.line + 1, mark.column + 1}, ChildPath(key) + ": unknown key",
                     hint);
  }
}

double ConfigNode::AsDouble() const {
  double value = 0;
  if (!node_.IsScalar() || !YAML::convert<double>::decode(node_, value)) {
    throw Error("expected a number, got " + Describe(node_), "Write a plain number");
  }
  if (!std::isfinite(value)) {
    throw Error("expected a finite number, got " + Describe(node_), "Write a finite number");
  }
  return value;
}

int ConfigNode::AsInt() const {
  int value = 0;
  if (!node_.IsScalar() || !YAML::convert<int>::decode(node_, value)) {
    throw Error("expected a whole number, got " + Describe(node_), "Write a whole number");
  }
  return value;
}

bool ConfigNode::AsBool() const {
  bool value = false;
  if (!node_.IsScalar() || !YAML::convert<bool>::decode(node_, value)) {
    throw Error("expected true or false, got " + Describe(node_), "Write true or false");
  }
  return value;
}

std::string ConfigNode::AsString() const {
  if (!node_.IsScalar()) throw Error("expected a text value, got " + Describe(node_));
  return node_.Scalar();
}

std::vector<double> ConfigNode::AsDoubles(std::optional<size_t> expected_size) const {
  ExpectSequence();
  if (expected_size && node_.size() != *expected_size) {
    throw Error("expected a list of " + std::to_string(*expected_size) + " numbers, got " +
                    std::to_string(node_.size()),
                "Give " + std::to_string(*expected_size) + " numbers in brackets");
  }
  std::vector<double> values;
  for (const auto& element : Elements()) values.push_back(element.AsDouble());
  return values;
}

std::vector<std::string> ConfigNode::AsStrings() const {
  if (node_.IsScalar()) return {node_.Scalar()};
  std::vector<std::string> values;
  for (const auto& element : Elements()) values.push_back(element.AsString());
  return values;
}

double ConfigNode::GetDouble(const std::string& key, double fallback) const {
  return Has(key) ? (*this)[key].AsDouble() : fallback;
}
int ConfigNode::GetInt(const std::string& key, int fallback) const {
  return Has(key) ? (*this)[key].AsInt() : fallback;
}
double ConfigNode::GetDoubleIn(const std::string& key, double fallback, double lo, double hi,
                               const std::string& hint) const {
  if (!Has(key)) return fallback;
  const double value = (*this)[key].AsDouble();
  if (!(value >= lo && value <= hi)) {
    char range[96];
    std::snprintf(range, sizeof(range), "must be between %g and %g", lo, hi);
    throw(*this)[key].Error(range, hint);
  }
  return value;
}
int ConfigNode::GetIntIn(const std::string& key, int fallback, int lo, int hi,
                         const std::string& hint) const {
  if (!Has(key)) return fallback;
  const int value = (*this)[key].AsInt();
  if (value < lo || value > hi) {
    throw(*this)[key].Error("must be between " + std::to_string(lo) + " and " + std::to_string(hi),
                            hint);
  }
  return value;
}
std::vector<double> ConfigNode::AsPositiveDoubles(size_t n) const {
  const std::vector<double> values = AsDoubles(n);
  for (double v : values) {
    if (!(v > 0.0)) {
      throw Error("every entry must be positive (a standard deviation)",
                  "A sigma of 0 says 'known perfectly': give the measurement's real scatter");
    }
  }
  return values;
}
bool ConfigNode::GetBool(const std::string& key, bool fallback) const {
  return Has(key) ? (*this)[key].AsBool() : fallback;
}
std::string ConfigNode::GetString(const std::string& key, const std::string& fallback) const {
  return Has(key) ? (*this)[key].AsString() : fallback;
}

std::string ConfigNode::ResolvePath(const std::string& path) const {
  const std::filesystem::path p(path);
  if (p.is_absolute() || file_.empty()) return p.lexically_normal().string();
  const std::filesystem::path base = std::filesystem::path(file_).parent_path();
  return (base / p).lexically_normal().string();
}

void CopyTextEntry(const ConfigNode& config, const std::string& key, std::ostream& out) {
  if (!config.Has(key)) return;
  YAML::Emitter text;
  text << config[key].AsString();
  out << key << ": " << text.c_str() << "\n";
}

}  // namespace cellmetry
