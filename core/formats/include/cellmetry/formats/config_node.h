// ConfigNode: a YAML node that knows which file and line it came from and its key path.
//
// Every reader of a YAML file (jobs, robot configs, plugin options) goes through this type so that
// every complaint about a file reads the same way:
//
//   job.yaml:12:5: error: robots.ur3.base.frees: unknown key. Did you mean 'free'? Known keys: ...
//
// Contract:
//  - A reader first calls ExpectKeys() with every key it understands; any other key is an error
//    (with a "did you mean" for near misses). Typos never pass silently.
//  - Typed getters (AsDouble, AsString, ...) throw InputError naming the key path and what type was
//    expected. Numbers must be finite.
//  - Relative paths in a file are resolved against that file's folder (ResolvePath).
#pragma once

#include <yaml-cpp/yaml.h>

#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"

namespace cellmetry {

class ConfigNode {
 public:
  // Loads a YAML file; a missing file or a syntax error raises InputError with the location.
  static ConfigNode LoadFile(const std::string& path);
  // Parses YAML text; `origin` names it in messages (e.g. a file path or "<command line>").
  static ConfigNode LoadString(const std::string& text, const std::string& origin);

  ConfigNode(YAML::Node node, std::string file, std::string key_path);

  const std::string& key_path() const { return key_path_; }
  const std::string& file() const { return file_; }
  SourceLocation location() const;

  bool IsMap() const { return node_.IsMap(); }
  bool IsSequence() const { return node_.IsSequence(); }
  bool IsScalar() const { return node_.IsScalar(); }
  bool IsNull() const { return !node_ || node_.IsNull(); }

  bool Has(const std::string& key) const;
  // The child under `key`; raises "missing key" when absent.
  ConfigNode operator[](const std::string& key) const;
  std::optional<ConfigNode> Optional(const std::string& key) const;
  // Keys of a map, in file order.
  std::vector<std::string> Keys() const;
  // Elements of a sequence.
  std::vector<ConfigNode> Elements() const;

  // Raises InputError for the first key not in `allowed`, suggesting the nearest known key.
  void ExpectKeys(const std::vector<std::string>& allowed) const;
  // Raises InputError unless this node is a map (or a sequence) at all.
  void ExpectMap() const;
  void ExpectSequence() const;

  double AsDouble() const;
  int AsInt() const;
  bool AsBool() const;
  std::string AsString() const;
  std::vector<double> AsDoubles(std::optional<size_t> expected_size = std::nullopt) const;
  std::vector<std::string> AsStrings() const;

  double GetDouble(const std::string& key, double fallback) const;
  int GetInt(const std::string& key, int fallback) const;
  bool GetBool(const std::string& key, bool fallback) const;
  std::string GetString(const std::string& key, const std::string& fallback) const;
  // As GetDouble / GetInt, refused at the value (file:line:column) outside [lo, hi], with `hint`.
  double GetDoubleIn(const std::string& key, double fallback, double lo, double hi,
                     const std::string& hint) const;
  int GetIntIn(const std::string& key, int fallback, int lo, int hi, const std::string& hint) const;
  // AsDoubles(n), every entry refused unless > 0 (a standard deviation, a size).
  std::vector<double> AsPositiveDoubles(size_t n) const;

  // A path written in this file, made absolute relative to the file's folder.
  std::string ResolvePath(const std::string& path) const;

  // Where `key` itself is written in this map (its value may be empty: `tool:`); this node's
  // location when the key is not there.
  SourceLocation KeyLocation(const std::string& key) const;

  // An InputError located at this node, with the key path in front of `what`.
  InputError Error(const std::string& what, const std::string& hint = "") const;

  const YAML::Node& yaml() const { return node_; }
  // This node as one line of YAML in flow style ("{type: backlash, joints: [2]}"), which
  // LoadString reads back to the same node: how a result records what built an effect.
  std::string FlowText() const;

 private:
  std::string ChildPath(const std::string& key) const;

  YAML::Node node_;
  std::string file_;
  std::string key_path_;
};

// The candidate nearest to `word` by edit distance, or "" when none is close enough to suggest.
std::string NearestWord(const std::string& word, const std::vector<std::string>& candidates);

// The line `key: value` for the string `config` has under `key`, quoted as YAML needs (a value
// with a colon or a quote stays one string), written to `out`; nothing when `config` has no
// `key`. What a robot model's CalibratedConfig copies from the config it was built from (its
// name and description).
void CopyTextEntry(const ConfigNode& config, const std::string& key, std::ostream& out);

}  // namespace cellmetry
