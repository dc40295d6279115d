// Date-time cells: an instrument's or a logger's clock as it writes it
// (`'20.10.2022 16:57:12.092`, `2022-10-20T16:57:12`), read as seconds.
//
// Contract:
//  - The format is strftime's subset that clocks write: %Y (four digits), %m, %d, %H, %M, %S
//    (each one or two digits; %S may carry a fraction after '.' or ','), %% for a '%'; every
//    other character must stand in the cell as it stands in the format. It must hold %Y, %m,
//    %d, %H and %M, each once.
//  - The value is the time since 1970-01-01 00:00:00 of the file's own clock, whole seconds and
//    the fraction apart (a double holding both would round a millisecond): no time zone and no
//    leap seconds are applied, so differences between cells of one file are exact.
//  - Spaces around the cell are ignored; anything else the format does not account for is a
//    problem, as is a field out of its range (month 13, 31 April, hour 24).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace cellmetry {

struct ClockTime {
  int64_t whole_s = 0;    // since 1970-01-01 00:00:00
  double fraction_s = 0;  // [0, 1)

  double SecondsSince(const ClockTime& earlier) const {
    return static_cast<double>(whole_s - earlier.whole_s) + (fraction_s - earlier.fraction_s);
  }
  bool operator<(const ClockTime& o) const {
    return whole_s < o.whole_s || (whole_s == o.whole_s && fraction_s < o.fraction_s);
  }
};

// Why `format` cannot read date-times (an unknown directive, a field missing or repeated);
// none when it can.
std::optional<std::string> DateTimeFormatProblem(const std::string& format);

// `text` read with `format` (above); none, with the reason in `problem`, otherwise.
std::optional<ClockTime> ParseDateTime(const std::string& text, const std::string& format,
                                       std::string* problem);

}  // namespace cellmetry
