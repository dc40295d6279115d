// Date-time cells read as seconds (date_time.h).
#include "cellmetry/import/date_time.h"

#include <cctype>
#include <cstdint>
#include <map>

#include "cellmetry/formats/quoted_text.h"

namespace cellmetry {
namespace {

constexpr char kDirectives[] = "YmdHMS";

// Days from 1970-01-01 to year-month-day of the proleptic Gregorian calendar (Hinnant's
// days_from_civil: eras of 400 years, March as the first month so that February comes last).
int64_t DaysFromCivil(int64_t year, int month, int day) {
  year -= month <= 2 ? 1 : 0;
  const int64_t era = (year >= 0 ? year : year - 399) / 400;
  const int64_t year_of_era = year - era * 400;
  const int64_t day_of_year = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;
  const int64_t day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  return era * 146097 + day_of_era - 719468;
}

int DaysInMonth(int64_t year, int month) {
  static constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  return month == 2 && leap ? 29 : kDays[month - 1];
}

// Reads up to `max_digits` digits (at least one) at text[*at].
std::optional<int> ReadDigits(const std::string& text, size_t* at, int max_digits) {
  int value = 0, digits = 0;
  while (*at < text.size() && digits < max_digits &&
         std::isdigit(static_cast<unsigned char>(text[*at]))) {
    value = value * 10 + (text[*at] - '0');
    ++*at;
    ++digits;
  }
  if (digits == 0) return std::nullopt;
  return value;
}

// A fraction of a second after '.' or ',' at text[*at], or 0.
double ReadFraction(const std::string& text, size_t* at) {
  if (*at + 1 >= text.size() || (text[*at] != '.' && text[*at] != ',') ||
      !std::isdigit(static_cast<unsigned char>(text[*at + 1]))) {
    return 0.0;
  }
  ++*at;
  double fraction = 0.0, scale = 0.1;
  while (*at < text.size() && std::isdigit(static_cast<unsigned char>(text[*at]))) {
    fraction += scale * (text[*at] - '0');
    scale *= 0.1;
    ++*at;
  }
  return fraction;
}

std::string Trimmed(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

}  // namespace

std::optional<std::string> DateTimeFormatProblem(const std::string& format) {
  std::map<char, int> seen;
  for (size_t i = 0; i < format.size(); ++i) {
    if (format[i] != '%') continue;
    if (i + 1 == format.size()) return "it ends in a lone '%' (write %% for a '%')";
    const char d = format[++i];
    if (d == '%') continue;
    if (std::string(kDirectives).find(d) == std::string::npos) {
      return std::string("it has %") + d + ", which is not one of %Y %m %d %H %M %S %%";
    }
    if (++seen[d] > 1) return std::string("it has %") + d + " twice";
  }
  for (char d : std::string("YmdHM")) {
    if (seen[d] == 0) return std::string("it has no %") + d + " (a date-time needs %Y %m %d %H %M)";
  }
  return std::nullopt;
}

std::optional<ClockTime> ParseDateTime(const std::string& text, const std::string& format,
                                       std::string* problem) {
  problem->clear();
  const std::string cell = Trimmed(text);
  const std::string quoted = "'" + QuotedShort(cell) + "'";
  std::map<char, int> field = {{'Y', 1970}, {'m', 1}, {'d', 1}, {'H', 0}, {'M', 0}, {'S', 0}};
  double fraction = 0.0;
  size_t at = 0;
  for (size_t i = 0; i < format.size(); ++i) {
    if (format[i] == '%' && i + 1 < format.size() && format[i + 1] != '%') {
      const char d = format[++i];
      const std::optional<int> value = ReadDigits(cell, &at, d == 'Y' ? 4 : 2);
      if (!value) {
        *problem = quoted + " does not read as " + format + ": no digits for %" + d +
                   " at character " + std::to_string(at + 1);
        return std::nullopt;
      }
      field[d] = *value;
      if (d == 'S') fraction = ReadFraction(cell, &at);
      continue;
    }
    if (format[i] == '%') ++i;  // %% stands for '%'
    if (at >= cell.size() || cell[at] != format[i]) {
      *problem = quoted + " does not read as " + format + ": expected '" + format[i] +
                 "' at character " + std::to_string(at + 1);
      return std::nullopt;
    }
    ++at;
  }
  if (at != cell.size()) {
    *problem = quoted + " does not read as " + format + ": '" + QuotedShort(cell.substr(at)) +
               "' is left over";
    return std::nullopt;
  }
  const int year = field['Y'], month = field['m'], day = field['d'];
  if (month < 1 || month > 12 || day < 1 || day > DaysInMonth(year, month) || field['H'] > 23 ||
      field['M'] > 59 || field['S'] > 60) {
    *problem = quoted + " is not a date and time (read as " + format + ")";
    return std::nullopt;
  }
  return ClockTime{
      DaysFromCivil(year, month, day) * 86400 + field['H'] * 3600 + field['M'] * 60 + field['S'],
      fraction};
}

}  // namespace cellmetry
