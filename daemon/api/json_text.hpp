#pragma once
// JSON text for an API reply. Strings in replies can come from outside rigd (a run's notes
// or eye id imported from someone's CSV, a lab-archive row written by another rig, a path a
// client sent); bytes that are not UTF-8 are replaced (U+FFFD) instead of making
// nlohmann's dump() throw, which would turn a reply into a 500.
#include <nlohmann/json.hpp>

#include <string>

namespace rig::api {

inline std::string json_text(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace rig::api
