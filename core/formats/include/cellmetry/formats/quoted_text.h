// A cell or a YAML value as an error message quotes it: an error is one line a person reads,
// and a 10 MB cell quoted whole made one of 10 MB.
#pragma once

#include <cstdio>
#include <string>

namespace cellmetry {

// At most 80 characters of `text` (then "..."), and what no terminal shows (a NUL, a control
// character) as \xNN.
inline std::string QuotedShort(const std::string& text) {
  std::string out;
  size_t i = 0;
  for (; i < text.size() && out.size() < 80; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", c);
      out += escaped;
    } else {
      out += text[i];
    }
  }
  return i < text.size() ? out + "..." : out;
}

// `what` with each occurrence of `text` (the cell or value it is about, quoted whole by the
// reader that raised it) cut to QuotedShort when it is longer than `longest`.
inline std::string WithTextShortened(std::string what, const std::string& text,
                                     size_t longest = 80) {
  if (text.size() <= longest) return what;
  const std::string short_text = QuotedShort(text);
  for (size_t at = what.find(text); at != std::string::npos; at = what.find(text, at)) {
    what.replace(at, text.size(), short_text);
    at += short_text.size();
  }
  return what;
}

}  // namespace cellmetry
