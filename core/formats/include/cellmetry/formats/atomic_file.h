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

// Never replaces what cellmetry did not write. Every output folder carries a marker file
// (kOutputMarker) naming its kind ("result", "recording", "homing", "comparison"); a folder is
// replaced only by output of the same kind. Throws InputError naming `path` when it is a file,
// a folder without the marker (a user's folder, a bundled recording, an older cellmetry's
// output), a folder of another kind (a job's output naming its own recording), or a folder that
// holds the working directory. Commands call it before their work, so that a long fit is not
// lost to a refusal at the end.
// The marker also lists the entries cellmetry wrote into the folder: a folder that holds
// anything else (a user's notes, photos) is refused too, since replacing it would move them
// aside and the next replacement delete them.
inline constexpr const char* kOutputMarker = ".cellmetry-output";
void CheckReplaceable(const std::string& path, const std::string& kind);

// Adds `name` to the list in `folder`'s marker: for a file a later command writes into a
// folder cellmetry made (`detect`'s observations.csv in a simulated recording). A folder
// without a marker is left as it is.
void NoteOutputFile(const std::string& folder, const std::string& name);

// A folder under construction: files go to staging(), Commit() renames it to `final_path`
// (replacing an older one of the same kind, CheckReplaceable, which stays recoverable as
// `<final_path>.previous`, one generation deep). If the object dies uncommitted,
// the staging folder is removed; staging folders that killed runs left beside `final_path` go
// when the next one starts.
class StagedDirectory {
 public:
  StagedDirectory(std::string final_path, std::string kind);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  const std::string& staging() const { return staging_; }
  std::string File(const std::string& name) const { return staging_ + "/" + name; }
  void Commit();

 private:
  std::string final_path_;
  std::string kind_;
  std::string staging_;
  bool committed_ = false;
};

}  // namespace cellmetry
