// Checkpoint: the finished pieces of long work, kept as they end, so that an interrupted command
// (`cellmetry compare`, `cellmetry diagnose`) resumes where it stopped instead of starting over.
//
// The pieces live in one JSON file beside the command's output (`<output>.partial.json`), keyed
// by a fingerprint of the inputs and the piece's own key (a seed, a row, a round), so that a
// piece written from edited inputs is never read back. Each Put rewrites the file atomically: a
// kill at any moment leaves the previous pieces or the new ones, and a file torn some other way
// reads as empty. The command removes the file once its output is written.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace cellmetry {

// The text of the file at `path`, hashed: what a checkpoint is keyed by ("" when unreadable).
std::string FileFingerprint(const std::string& path);
// Every file under `folder` (a recording), by relative name, size and modification time,
// hashed: a file added, removed, rewritten or touched changes it. Contents are not read (a
// recording's images may be gigabytes). "" when the folder cannot be listed.
std::string FolderFingerprint(const std::string& folder);

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
