// Text encodings a table may be written in (the check that UTF-8 text is UTF-8:
// basics/utf8.h).
//
// Contract: cellmetry works in UTF-8. A table in an 8-bit encoding (what measuring software on
// Windows writes: `°C`, `µm` as one byte each) is converted to UTF-8 as it is read, when the
// mapping says which encoding it is; it is never guessed. Windows-1252 is read for `latin1`
// too, as browsers do (the WHATWG Encoding Standard): it is ISO-8859-1 with printable
// characters (the euro sign, dashes, curly quotes) where ISO-8859-1 has unused control codes
// 0x80-0x9F; the five bytes Windows-1252 leaves undefined become those control codes.
#pragma once

#include <optional>
#include <string>

namespace cellmetry {

enum class TextEncoding { kUtf8, kWindows1252 };

// "utf-8" | "latin1" | "windows-1252" | "cp1252" (case as written): the names a mapping accepts.
std::optional<TextEncoding> TextEncodingNamed(const std::string& name);

// `bytes` in Windows-1252, as UTF-8 (every byte is a character; ASCII is unchanged).
std::string Windows1252ToUtf8(const std::string& bytes);

}  // namespace cellmetry
