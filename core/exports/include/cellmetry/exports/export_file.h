// Writing an export file without losing anything that was there.
//
// An export is one file a user puts anywhere (a ROS package's config folder, next to their own
// files), so the marker file that guards cellmetry's output folders (atomic_file.h) does not fit.
// Instead every export carries the word kExportMarker in its opening comment (export_header.h),
// and WriteExportFile decides by it:
//
//   nothing at `path`            written
//   an earlier export            replaced; the old one stays beside it as <path>.previous
//   any other file               refused (InputError naming the path, exit code 2), unless
//                                `overwrite`: then replaced and kept as <path>.previous too
//   a folder                     refused
//
// The <path>.previous slot is itself replaced only when it is empty or holds an earlier export:
// a user's file there is never lost (the refusal says to move it). The new text is written
// atomically (AtomicWriteFile); if that fails, the old file is put back.
#pragma once

#include <string>

namespace cellmetry {

inline constexpr const char* kExportMarker = "cellmetry-export";

// Whether `path` is a file whose first 4 kB carry kExportMarker.
bool IsCellmetryExport(const std::string& path);

// Throws InputError unless WriteExportFile(path, ..., overwrite) may write: commands call it
// before their work.
void CheckExportTarget(const std::string& path, bool overwrite);

void WriteExportFile(const std::string& path, const std::string& text, bool overwrite);

}  // namespace cellmetry
