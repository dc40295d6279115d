// Whether text is UTF-8, and where it stops being it.
//
// Contract: cellmetry works in UTF-8, and a reader that hands text to a parser which trusts it
// (TinyXML walks a multi-byte character by its first byte's count, past the end of the text when
// the character is cut short) checks it first. Well-formed is RFC 3629's: no overlong forms, no
// surrogates, nothing beyond U+10FFFF. A NUL byte is UTF-8 (U+0000); a reader that cannot take
// one says so itself.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace cellmetry {

// The offset of the first byte in `text` that does not belong to a well-formed UTF-8 sequence;
// none when it is UTF-8.
std::optional<size_t> FirstInvalidUtf8Byte(const std::string& text);

}  // namespace cellmetry
