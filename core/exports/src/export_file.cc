// Export files that never replace what cellmetry did not write (export_file.h).
#include "cellmetry/exports/export_file.h"

#include <filesystem>
#include <fstream>

#include "cellmetry/basics/error.h"
#include "cellmetry/formats/atomic_file.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

const char kElsewhere[] = "Choose another file with -o";

bool Exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

// What is at `path` may be set aside as <path>.previous: nothing, or an earlier export.
void CheckPreviousSlot(const std::string& path) {
  const std::string previous = path + ".previous";
  if (!Exists(previous) || IsCellmetryExport(previous)) return;
  throw InputError({previous, 0, 0},
                   "the file that keeps the replaced export is not one "
                   "cellmetry wrote; it is left as it is",
                   "Move it away, or " + std::string(kElsewhere));
}

}  // namespace

bool IsCellmetryExport(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  return head.find(kExportMarker) != std::string::npos;
}

void CheckExportTarget(const std::string& path, bool overwrite) {
  if (!Exists(path)) return;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError({path, 0, 0}, "the export path is not a file (a folder?)", kElsewhere);
  }
  if (!IsCellmetryExport(path) && !overwrite) {
    throw InputError({path, 0, 0},
                     "the file exists and was not written by `cellmetry export` "
                     "(no '" +
                         std::string(kExportMarker) +
                         "' in its first lines); it is left "
                         "as it is",
                     std::string(kElsewhere) +
                         ", or give --overwrite to replace it "
                         "(it is then kept as " +
                         path + ".previous)");
  }
  CheckPreviousSlot(path);
}

void WriteExportFile(const std::string& path, const std::string& text, bool overwrite) {
  CheckExportTarget(path, overwrite);
  const std::string previous = path + ".previous";
  std::error_code ec;
  const bool replacing = Exists(path);
  if (replacing) {
    fs::rename(path, previous, ec);  // replaces an earlier export kept there (checked above)
    if (ec) {
      throw InputError({path, 0, 0}, "cannot set the replaced export aside as " + previous,
                       "Check permissions on the folder");
    }
  }
  try {
    AtomicWriteFile(path, text);
  } catch (...) {
    if (replacing) fs::rename(previous, path, ec);
    throw;
  }
}

}  // namespace cellmetry
