#include "support/test_support.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cellmetry/progress.h"

namespace fs = std::filesystem;

namespace cellmetry::testing {

Registry& Plugins() {
  static bool loaded = [] {
    Progress::SetQuiet(true);
    Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  return Registry::Global();
}

std::string Source(const std::string& relative) {
  return std::string(CELLMETRY_SOURCE_DIR) + "/" + relative;
}

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::path(CELLMETRY_BUILD_DIR) / "test_tmp" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

void WriteText(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

CommandResult RunCellmetry(const std::string& arguments) {
  const std::string command = std::string(CELLMETRY_BINARY) + " -q " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace cellmetry::testing
