// Output that is either whole or absent.
//
// Every file cellmetry writes goes through AtomicWriteFile: the text is written to a temporary
// file beside the target and renamed over it only once complete, so an interrupted or failed
// run never leaves a half-written result behind. Folders (a recording, a result set) are built
// in a temporary sibling and renamed into place by CommitDirectory.
#pragma once

#include <string>

namespace cellmetry {

// Writes `text` to `path` atomically; creates missing parent folders. Throws InputError when the
// folder cannot be written.
void AtomicWriteFile(const std::string& path, const std::string& text);

// A folder under construction: files go to staging(), Commit() renames it to `final_path`
// (replacing an older one). If the object dies uncommitted, the staging folder is removed.
class StagedDirectory {
 public:
  explicit StagedDirectory(std::string final_path);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  const std::string& staging() const { return staging_; }
  std::string File(const std::string& name) const { return staging_ + "/" + name; }
  void Commit();

 private:
  std::string final_path_;
  std::string staging_;
  bool committed_ = false;
};

}  // namespace cellmetry
