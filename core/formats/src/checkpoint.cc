// Finished pieces of long work, kept and read back (checkpoint.h).
#include "cellmetry/formats/checkpoint.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <system_error>
#include <vector>

#include "cellmetry/formats/atomic_file.h"

namespace cellmetry {

std::string FileFingerprint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  return std::to_string(std::hash<std::string>{}(text));
}

std::string FolderFingerprint(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::recursive_directory_iterator it(folder, error), end;
  if (error) return "";
  std::vector<std::string> entries;  // sorted below: the listing's order is the filesystem's
  for (; it != end; it.increment(error)) {
    if (error) return "";
    if (!it->is_regular_file(error)) continue;
    const auto size = it->file_size(error);
    const auto time = it->last_write_time(error).time_since_epoch().count();
    entries.push_back(fs::relative(it->path(), folder).generic_string() + " " +
                      std::to_string(size) + " " + std::to_string(time));
  }
  std::sort(entries.begin(), entries.end());
  std::string listing;
  for (const std::string& entry : entries) listing += entry + "\n";
  return std::to_string(std::hash<std::string>{}(listing));
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
