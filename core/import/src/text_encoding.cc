// Text encodings (text_encoding.h): Windows-1252 to UTF-8.
#include "cellmetry/import/text_encoding.h"

#include <cstdint>

namespace cellmetry {
namespace {

// Windows-1252's bytes 0x80-0x9F as Unicode code points (0x81 0x8D 0x8F 0x90 0x9D: undefined,
// kept as the C1 control of the same number, as the WHATWG Encoding Standard does).
constexpr uint16_t kHighControls[32] = {
    0x20AC, 0x0081, 0x201A, 0x0192, 0x201E, 0x2026, 0x2020, 0x2021,  // 80-87
    0x02C6, 0x2030, 0x0160, 0x2039, 0x0152, 0x008D, 0x017D, 0x008F,  // 88-8F
    0x0090, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022, 0x2013, 0x2014,  // 90-97
    0x02DC, 0x2122, 0x0161, 0x203A, 0x0153, 0x009D, 0x017E, 0x0178,  // 98-9F
};

void AppendUtf8(uint32_t code_point, std::string* out) {
  if (code_point < 0x80) {
    out->push_back(static_cast<char>(code_point));
  } else if (code_point < 0x800) {
    out->push_back(static_cast<char>(0xC0 | (code_point >> 6)));
    out->push_back(static_cast<char>(0x80 | (code_point & 0x3F)));
  } else {  // Windows-1252 reaches no further than U+FFFF
    out->push_back(static_cast<char>(0xE0 | (code_point >> 12)));
    out->push_back(static_cast<char>(0x80 | ((code_point >> 6) & 0x3F)));
    out->push_back(static_cast<char>(0x80 | (code_point & 0x3F)));
  }
}

}  // namespace

std::optional<TextEncoding> TextEncodingNamed(const std::string& name) {
  if (name == "utf-8" || name == "utf8" || name == "UTF-8") return TextEncoding::kUtf8;
  for (const char* alias : {"latin1", "latin-1", "iso-8859-1", "windows-1252", "cp1252"}) {
    if (name == alias) return TextEncoding::kWindows1252;
  }
  return std::nullopt;
}

std::string Windows1252ToUtf8(const std::string& bytes) {
  std::string text;
  text.reserve(bytes.size() + bytes.size() / 8);
  for (const char c : bytes) {
    const auto byte = static_cast<unsigned char>(c);
    AppendUtf8(byte >= 0x80 && byte < 0xA0 ? kHighControls[byte - 0x80] : byte, &text);
  }
  return text;
}

}  // namespace cellmetry
