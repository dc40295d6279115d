// Text made safe for XML and HTML: the one escaping function that the exports (URDF, launch
// files) and the report (HTML pages, inline SVG) share.
#pragma once

#include <string>

namespace cellmetry {

// `text` with & < > " replaced by their entities: safe as element text and inside an attribute
// value in double quotes. Every other byte (UTF-8 included) passes unchanged.
std::string EscapeXml(const std::string& text);

}  // namespace cellmetry
