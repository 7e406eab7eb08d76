#pragma once
// JSON parsed with bounded nesting and no duplicate keys (issue #18; limits in core/limits.h).
// Header-only: included by the modules that link nlohmann_json (cache, scene, cli).
//
// nlohmann::json parses iteratively but dump() recurses once per level, so a 100 000-deep
// document in a .nph index or a scene's "animation" overflowed the stack long after parsing.
// The parser callback sees every nesting step with its depth, so the document is refused while
// it is read. The same callback tracks the keys of each open object: RFC 8259 §4 says names
// SHOULD be unique, and nlohmann silently keeps the last value, so {"fov_deg": 30, "fov_deg": 90}
// would render at 90 without a word.
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/limits.h"

namespace nph::json_limits {

/// Parses `text` (named `file` in errors; `what` says what the document is, e.g. "scene file").
/// InputError "<file>: not valid JSON (<what>): ..." on syntax errors, nesting deeper than
/// limits::kMaxJsonDepth, or a key given twice in one object.
inline nlohmann::json parse(std::string_view text, const std::string& file, const std::string& what,
                            bool ignore_comments = false) {
  using json = nlohmann::json;
  // One entry per open container: the keys seen so far (arrays get an unused empty set).
  std::vector<std::set<std::string>> keys;
  std::string error;
  const json::parser_callback_t check = [&](int depth, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (depth >= limits::kMaxJsonDepth) {
          throw InputError(fmt::format("{}: {} nests deeper than {} levels (limits::kMaxJsonDepth); "
                                       "refused to protect the stack",
                                       file, what, limits::kMaxJsonDepth));
        }
        keys.emplace_back();
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!keys.empty()) keys.pop_back();
        break;
      case json::parse_event_t::key:
        if (!keys.empty() && parsed.is_string() && !keys.back().insert(parsed.get<std::string>()).second) {
          throw InputError(fmt::format("{}: {}: key \"{}\" appears twice in one object (at depth {}), "
                                       "expected each key once",
                                       file, what, parsed.get<std::string>(), depth));
        }
        break;
      case json::parse_event_t::value: break;
    }
    return true;
  };
  try {
    return json::parse(text.begin(), text.end(), check, /*allow_exceptions=*/true, ignore_comments);
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON ({}): {}", file, what, e.what()));
  }
}

}  // namespace nph::json_limits
