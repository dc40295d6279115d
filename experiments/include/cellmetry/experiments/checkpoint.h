// Checkpoint: the finished pieces of a long comparison, kept as they end, so that an interrupted
// `cellmetry compare` resumes where it stopped instead of starting over.
//
// The pieces live in one JSON file beside the comparison's output (`<output>.partial.json`),
// keyed by the spec's fingerprint and the piece's own key (a seed, a row), so that a piece
// written under an edited spec is never read back. Each Put rewrites the file atomically: a
// kill at any moment leaves the previous pieces or the new ones, and a file torn some other way
// reads as empty. The comparison's caller removes the file once the tables are written.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace cellmetry {

// The text of the file at `path`, hashed: what a checkpoint is keyed by ("" when unreadable).
std::string FileFingerprint(const std::string& path);

class Checkpoint {
 public:
  // `path` empty: nothing is kept or read.
  Checkpoint(std::string path, std::string fingerprint);

  // The piece `key` finished before under this fingerprint, or null.
  const nlohmann::json* Find(const std::string& key) const;
  // Keeps `piece` under `key`, written to the file at once.
  void Put(const std::string& key, nlohmann::json piece);

 private:
  std::string path_;
  std::string fingerprint_;
  nlohmann::json pieces_ = nlohmann::json::object();
};

}  // namespace cellmetry
