// Whole-or-absent output (atomic_file.h): a file is written to a temporary beside its target and
// renamed over it; a folder is staged in a temporary sibling and renamed into place.
#include "cellmetry/formats/atomic_file.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include "cellmetry/basics/error.h"

namespace fs = std::filesystem;

namespace cellmetry {

void AtomicWriteFile(const std::string& path, const std::string& text) {
  const fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  const std::string temporary = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw InputError({path, 0, 0}, "cannot write file",
                       "Check that the folder exists and is writable");
    }
    out << text;
    out.flush();
    if (!out) {
      fs::remove(temporary, ec);
      throw InputError({path, 0, 0}, "writing failed", "Check free disk space");
    }
  }
  fs::rename(temporary, target, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw InputError({path, 0, 0}, "cannot replace file", "Check permissions on the folder");
  }
}

namespace {

std::string Normalized(const std::string& path) {
  fs::path target = fs::path(path).lexically_normal();
  if (target.filename().empty()) target = target.parent_path();
  return target.string();
}

// `folder`'s marker: its kind ("" when it has none) and the entries cellmetry wrote there.
struct Marker {
  std::string kind;
  std::set<std::string> wrote;  // empty in a marker older than the list
};

constexpr const char* kWrote = "wrote: ";

Marker ReadMarker(const fs::path& folder) {
  Marker marker;
  std::ifstream in(folder / kOutputMarker);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("kind: ", 0) == 0) marker.kind = line.substr(6);
    if (line.rfind(kWrote, 0) == 0) marker.wrote.insert(line.substr(std::strlen(kWrote)));
  }
  return marker;
}

std::string MarkerKind(const fs::path& folder) { return ReadMarker(folder).kind; }

std::string MarkerText(const std::string& kind, const std::set<std::string>& wrote) {
  std::string text = "kind: " + kind + "\nwritten by cellmetry: a later " + kind +
                     " to this path replaces this folder\n";
  for (const auto& name : wrote) text += kWrote + name + "\n";
  return text;
}

// A temporary file a killed write left behind (AtomicWriteFile's NAME.tmpPID).
bool IsLeftoverTemporary(const std::string& name) {
  const size_t at = name.rfind(".tmp");
  return at != std::string::npos && at + 4 < name.size() &&
         name.find_first_not_of("0123456789", at + 4) == std::string::npos;
}

// The first entry of a marked `folder` that cellmetry did not write there ("" when none): not
// in the marker's list, not a folder of cellmetry's own (a diagnosis inside a result), not a
// leftover temporary. Replacing the folder would move it aside and, a run later, delete it.
std::string ForeignEntry(const fs::path& folder, const Marker& marker) {
  if (marker.wrote.empty()) return "";  // an older marker: no list to tell by
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name == kOutputMarker || marker.wrote.count(name) || IsLeftoverTemporary(name)) continue;
    if (entry.is_directory(ec) && !entry.is_symlink(ec) && !MarkerKind(entry.path()).empty()) {
      continue;
    }
    return name;
  }
  return "";
}

// A folder without a marker whose every entry is a folder cellmetry wrote (a job's output
// folder that so far holds only its diagnosis): nothing in it is the user's.
bool OnlyCellmetryOutput(const fs::path& folder) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (!entry.is_directory() || MarkerKind(entry.path()).empty()) return false;
  }
  return !ec;
}

// `inner` is `outer` or lies inside it.
bool Contains(const fs::path& outer, const fs::path& inner) {
  const auto [end, ignored] = std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end());
  return end == outer.end();
}

// Staging and set-aside folders beside `final_path` whose process is gone (a killed run).
void RemoveStaleStaging(const std::string& final_path) {
  const fs::path target(final_path);
  const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string name = target.filename().string();
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(parent, ec)) {
    const std::string other = entry.path().filename().string();
    for (const std::string suffix : {".partial", ".old"}) {
      const std::string prefix = name + suffix;
      if (other.size() <= prefix.size() || other.rfind(prefix, 0) != 0) continue;
      const std::string pid = other.substr(prefix.size());
      if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
      if (::kill(std::stoi(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to tell
      std::error_code ignored;
      fs::remove_all(entry.path(), ignored);
    }
  }
}

}  // namespace

void CheckReplaceable(const std::string& path, const std::string& kind) {
  const std::string target = Normalized(path);
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(target, ec);
  if (!fs::exists(status)) return;
  const std::string keep = "Choose another output folder (output: in the job, or -o)";
  if (!fs::is_directory(status)) {
    throw InputError({target, 0, 0},
                     "the output path is an existing file; cellmetry writes a "
                     "folder there and would replace it",
                     keep);
  }
  const fs::path absolute = fs::weakly_canonical(target, ec);
  if (Contains(absolute, fs::current_path(ec))) {
    throw InputError({target, 0, 0}, "the output folder holds the working directory", keep);
  }
  const Marker marker = ReadMarker(target);
  const std::string& found = marker.kind;
  if (found.empty() && !OnlyCellmetryOutput(target)) {
    throw InputError({target, 0, 0},
                     "the output folder exists and was not written by cellmetry "
                     "(no " +
                         std::string(kOutputMarker) + " in it); it is left as it is",
                     keep + ", or remove it yourself (an older cellmetry's output too)");
  }
  if (!found.empty() && found != kind) {
    throw InputError(
        {target, 0, 0},
        "the output folder holds a cellmetry " + found + ", which a " + kind + " would replace",
        keep);
  }
  if (const std::string foreign = ForeignEntry(target, marker); !foreign.empty()) {
    throw InputError({target, 0, 0},
                     "the output folder holds '" + foreign +
                         "', which cellmetry "
                         "did not write; replacing the folder would move it to " +
                         fs::path(target).filename().string() +
                         ".previous, and the run after "
                         "would delete it",
                     "Move '" + foreign +
                         "' out of the folder, or choose another output folder "
                         "(output: in the job, or -o)");
  }
  CheckReplaceable(target + ".previous", kind);  // where the replaced one will go
}

void NoteOutputFile(const std::string& folder, const std::string& name) {
  Marker marker = ReadMarker(folder);
  if (marker.kind.empty() || marker.wrote.empty() || marker.wrote.count(name)) return;
  marker.wrote.insert(name);
  AtomicWriteFile((fs::path(folder) / kOutputMarker).string(),
                  MarkerText(marker.kind, marker.wrote));
}

StagedDirectory::StagedDirectory(std::string final_path, std::string kind)
    : final_path_(Normalized(final_path)), kind_(std::move(kind)) {
  CheckReplaceable(final_path_, kind_);
  RemoveStaleStaging(final_path_);
  staging_ = final_path_ + ".partial" + std::to_string(::getpid());
  std::error_code ec;
  fs::remove_all(staging_, ec);
  fs::create_directories(staging_, ec);
  if (ec) {
    throw InputError({final_path_, 0, 0}, "cannot create output folder",
                     "Check that the parent folder is writable");
  }
  std::ofstream(fs::path(staging_) / kOutputMarker) << MarkerText(kind_, {});
}

StagedDirectory::~StagedDirectory() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

// The output this one replaces stays recoverable beside it, one generation deep:
// <final>.previous (an older .previous of the same kind goes; anything else there is refused).
void StagedDirectory::Commit() {
  CheckReplaceable(final_path_, kind_);  // nothing appeared there meanwhile
  // The marker lists what this run wrote: anything else found in the folder later is a user's,
  // and a rerun refuses the folder rather than move it aside (ForeignEntry).
  std::set<std::string> wrote;
  std::error_code list_error;
  for (const auto& entry : fs::directory_iterator(staging_, list_error)) {
    const std::string name = entry.path().filename().string();
    if (name != kOutputMarker) wrote.insert(name);
  }
  wrote.insert(kOutputMarker);  // never empty: an empty list reads as an older marker
  AtomicWriteFile((fs::path(staging_) / kOutputMarker).string(), MarkerText(kind_, wrote));
  const std::string previous = final_path_ + ".previous";
  const std::string older = previous + ".old" + std::to_string(::getpid());
  std::error_code ec;
  if (fs::exists(final_path_)) {
    CheckReplaceable(previous, kind_);
    if (fs::exists(previous)) fs::rename(previous, older, ec);
    if (!ec) fs::rename(final_path_, previous, ec);
    if (ec) {
      throw InputError({final_path_, 0, 0}, "cannot set the previous output aside",
                       "Check permissions on the parent folder");
    }
  }
  fs::rename(staging_, final_path_, ec);
  if (ec) {
    std::error_code ignored;
    if (fs::exists(previous) && !fs::exists(final_path_))
      fs::rename(previous, final_path_, ignored);
    throw InputError({final_path_, 0, 0}, "cannot move the finished output into place",
                     "Check permissions on the parent folder");
  }
  fs::remove_all(older, ec);
  committed_ = true;
}

}  // namespace cellmetry
