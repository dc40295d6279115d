// Errors that a user can act on.
//
// cellmetry tells bad input apart from bugs. Bad input (a file that is missing, a key that is
// misspelt, a value that is not a number) raises InputError, which carries where the problem is
// (file, line, column; 0 = unknown) and what to do about it. The command line prints it on one
// line as
//
//   FILE:LINE:COLUMN: error: WHAT. HINT
//
// and exits with code 2 (kInputErrorExitCode). Anything else is a bug and exits with 1.
#pragma once

#include <stdexcept>
#include <string>

namespace cellmetry {

inline constexpr int kInputErrorExitCode = 2;

struct SourceLocation {
  std::string file;  // path as the user gave it; empty when the input is not a file
  int line = 0;      // 1-based; 0 = unknown
  int column = 0;    // 1-based; 0 = unknown
};

class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, std::string what, std::string hint = "");

  const SourceLocation& where() const { return where_; }
  const std::string& message() const { return message_; }
  const std::string& hint() const { return hint_; }

 private:
  SourceLocation where_;
  std::string message_;
  std::string hint_;
};

// "FILE:LINE:COLUMN: " with the unknown parts left out; "" when the location is empty.
std::string FormatLocation(const SourceLocation& where);

}  // namespace cellmetry
