// Regular files of a bounded size, or an InputError (input_file.h).
#include "cellmetry/formats/input_file.h"

#include <sys/stat.h>

#include <fstream>
#include <iterator>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

std::string Megabytes(std::uintmax_t bytes) {
  return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB";
}

}  // namespace

void RequireRegularFile(const std::string& path, std::uintmax_t max_bytes,
                        const std::string& missing_hint) {
  // stat, not open: opening a FIFO for reading blocks until someone writes to it.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw InputError({path, 0, 0}, "cannot open file", missing_hint);
  }
  if (S_ISDIR(info.st_mode)) {
    throw InputError({path, 0, 0}, "is a folder, not a file", "Give the path of the file itself");
  }
  if (!S_ISREG(info.st_mode)) {
    const char* kind = S_ISFIFO(info.st_mode)   ? "a FIFO (named pipe)"
                       : S_ISCHR(info.st_mode)  ? "a character device"
                       : S_ISBLK(info.st_mode)  ? "a block device"
                       : S_ISSOCK(info.st_mode) ? "a socket"
                                                : "not a regular file";
    throw InputError({path, 0, 0},
                     std::string("is ") + kind + ", not a regular file; cellmetry reads files only",
                     "Put a regular file there: copy the data into one (a link may name a file, "
                     "not a pipe or a device)");
  }
  if (static_cast<std::uintmax_t>(info.st_size) > max_bytes) {
    throw InputError({path, 0, 0},
                     "is " + Megabytes(static_cast<std::uintmax_t>(info.st_size)) +
                         ", more than the " + Megabytes(max_bytes) +
                         " cellmetry reads from a file of this kind",
                     "Check that this is the right file; split a longer recording into several");
  }
}

std::string ReadRegularFile(const std::string& path, std::uintmax_t max_bytes,
                            const std::string& missing_hint) {
  RequireRegularFile(path, max_bytes, missing_hint);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, 0}, "cannot open file", "Check the file's permissions");
  std::string text;
  char buffer[1 << 16];
  // A file that grows while it is read stops at the limit all the same.
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<size_t>(in.gcount()));
    if (text.size() > max_bytes) {
      throw InputError({path, 0, 0}, "grew beyond " + Megabytes(max_bytes) + " while being read",
                       "Wait until whatever writes it has finished, then run again");
    }
  }
  return text;
}

}  // namespace cellmetry
