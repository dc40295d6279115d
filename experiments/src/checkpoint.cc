// Finished pieces of a comparison, kept and read back (checkpoint.h).
#include "cellmetry/experiments/checkpoint.h"

#include <fstream>
#include <functional>
#include <iterator>

#include "cellmetry/formats/atomic_file.h"

namespace cellmetry {

std::string FileFingerprint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  return std::to_string(std::hash<std::string>{}(text));
}

Checkpoint::Checkpoint(std::string path, std::string fingerprint)
    : path_(std::move(path)), fingerprint_(std::move(fingerprint)) {
  if (path_.empty()) return;
  std::ifstream in(path_);
  if (!in) return;
  try {
    pieces_ = nlohmann::json::parse(in);
    if (!pieces_.is_object()) pieces_ = nlohmann::json::object();
  } catch (const nlohmann::json::exception&) {
    pieces_ = nlohmann::json::object();  // torn some other way: start over
  }
}

const nlohmann::json* Checkpoint::Find(const std::string& key) const {
  const auto it = pieces_.find(fingerprint_ + "/" + key);
  return it == pieces_.end() ? nullptr : &*it;
}

void Checkpoint::Put(const std::string& key, nlohmann::json piece) {
  if (path_.empty()) return;
  pieces_[fingerprint_ + "/" + key] = std::move(piece);
  AtomicWriteFile(path_, pieces_.dump(1));
}

}  // namespace cellmetry
