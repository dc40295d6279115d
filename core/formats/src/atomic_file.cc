// Whole-or-absent output (atomic_file.h): a file is written to a temporary beside its target and
// renamed over it; a folder is staged in a temporary sibling and renamed into place.
#include "cellmetry/formats/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

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

StagedDirectory::StagedDirectory(std::string final_path) : final_path_(std::move(final_path)) {
  fs::path target = fs::path(final_path_).lexically_normal();
  if (target.filename().empty()) target = target.parent_path();
  final_path_ = target.string();
  staging_ = final_path_ + ".partial" + std::to_string(::getpid());
  std::error_code ec;
  fs::remove_all(staging_, ec);
  fs::create_directories(staging_, ec);
  if (ec) {
    throw InputError({final_path_, 0, 0}, "cannot create output folder",
                     "Check that the parent folder is writable");
  }
}

StagedDirectory::~StagedDirectory() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

void StagedDirectory::Commit() {
  std::error_code ec;
  const std::string old = final_path_ + ".old" + std::to_string(::getpid());
  if (fs::exists(final_path_)) fs::rename(final_path_, old, ec);
  fs::rename(staging_, final_path_, ec);
  if (ec) {
    throw InputError({final_path_, 0, 0}, "cannot move the finished output into place",
                     "Check permissions on the parent folder");
  }
  fs::remove_all(old, ec);
  committed_ = true;
}

}  // namespace cellmetry
