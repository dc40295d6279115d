// InputError's one-line message (error.h): FILE:LINE:COLUMN: error: WHAT. HINT, with the unknown
// parts of the location left out (FormatLocation).
#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

std::string Compose(const SourceLocation& where, const std::string& what, const std::string& hint) {
  std::string text = FormatLocation(where) + "error: " + what;
  if (!hint.empty()) text += ". " + hint;
  return text;
}

}  // namespace

InputError::InputError(SourceLocation where, std::string what, std::string hint)
    : std::runtime_error(Compose(where, what, hint)), where_(std::move(where)),
      message_(std::move(what)), hint_(std::move(hint)) {}

std::string FormatLocation(const SourceLocation& where) {
  if (where.file.empty()) return "";
  std::string text = where.file;
  if (where.line > 0) {
    text += ":" + std::to_string(where.line);
    if (where.column > 0) text += ":" + std::to_string(where.column);
  }
  return text + ": ";
}

}  // namespace cellmetry
