// Helpers shared by the test suites.
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "cellmetry/basics/error.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry::testing {

// The global registry with the plugins of this build loaded (once).
Registry& Plugins();

// Absolute path of a file in the source tree, e.g. Source("tests/data/vsb/sim_b").
std::string Source(const std::string& relative);

// A fresh, empty temporary folder for one test.
std::string TempDir(const std::string& name);
// TempDir("<folder>/<name of the running test>").
std::string TempDirForThisTest(const std::string& folder);

// Writes `text` to `path` (creating folders).
void WriteText(const std::string& path, const std::string& text);
std::string ReadText(const std::string& path);

// Replaces the one occurrence of `from` in `text`; fails the test if it is not there once.
std::string ReplaceOnce(const std::string& text, const std::string& from, const std::string& to);

// Replaces line `line` (1-based) of the file at `path`.
void EditLine(const std::string& path, int line, const std::string& replacement);

struct CommandResult {
  int exit_code = 0;
  std::string output;  // stdout and stderr together
};

// Runs `action`, which must raise InputError, and returns the error (a test failure if it does not).
template <typename Action>
InputError CatchInputError(Action action) {
  try {
    action();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError";
  return InputError({}, "no error raised");
}

// Runs the built `cellmetry` binary with `arguments` (a shell-quoted string).
CommandResult RunCellmetry(const std::string& arguments);

// The contract for bad input through the CLI: exit code 2 and one line
// "<location> error: ... <text> ..." (location e.g. "job.yaml:12:1:").
void ExpectOneLineError(const CommandResult& result, const std::string& location,
                        const std::string& text);

}  // namespace cellmetry::testing
