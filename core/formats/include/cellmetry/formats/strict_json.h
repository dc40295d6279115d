// JSON read as written or refused: a key twice in one object and nesting deeper than any
// cellmetry file needs are refused while parsing.
//
// nlohmann::json keeps one of two equal keys without a word (a line that says "q1" twice means
// one of them by mistake, as in YAML, where the same is refused). A value nested 20,000 deep is
// no table a user writes, and the flattening that follows parsing recurses once per level.
#pragma once

#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cellmetry {

// Objects and arrays inside one another, the outermost counted: a table row with a pose in it
// is 3 or 4 deep.
inline constexpr size_t kMaxJsonDepth = 64;

// What ParseStrictJson refuses; nlohmann's own exceptions (syntax, a number beyond a double's
// range) pass through as they are.
struct StrictJsonError {
  std::string what;
  std::string hint;
};

template <class Json>
Json ParseStrictJson(const std::string& text) {
  std::vector<std::set<std::string>> open;  // the keys of each object or array being read
  auto check = [&open](int, typename Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start:
        if (open.size() >= kMaxJsonDepth) {
          throw StrictJsonError{
              "objects and arrays nested deeper than " + std::to_string(kMaxJsonDepth) + " levels",
              "A row's values nest a few levels at most: {\"pose\": {\"t\": [x, y, z]}}"};
        }
        open.emplace_back();
        break;
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end: open.pop_back(); break;
      case Json::parse_event_t::key:
        if (!open.back().insert(parsed.template get<std::string>()).second) {
          std::string key = parsed.template get<std::string>();
          if (key.size() > 80) key = key.substr(0, 77) + "...";  // an error line stays a line
          throw StrictJsonError{"key '" + key + "' appears twice in one object",
                                "Keep one of them"};
        }
        break;
      default: break;
    }
    return true;
  };
  return Json::parse(text, check);
}

}  // namespace cellmetry
