#include "proto_runtime.hpp"

#include <cmath>
#include <regex>
#include <unordered_map>

namespace rig::proto {

ProtoError::ProtoError(std::string field, std::string reason)
    : std::runtime_error(field.empty() ? reason : "field '" + field + "': " + reason),
      field_(std::move(field)),
      reason_(std::move(reason)) {}

namespace detail {

void require_object(const nlohmann::json& j, const char* message) {
  if (!j.is_object()) throw ProtoError("", std::string("expected a JSON object (") + message + ")");
}

void reject_unknown(const nlohmann::json& j, std::initializer_list<const char*> known) {
  for (const auto& [key, value] : j.items()) {
    bool found = false;
    for (const char* k : known) found = found || key == k;
    if (!found) throw ProtoError(key, "unknown field");
  }
}

const nlohmann::json* field(const nlohmann::json& j, const char* key, bool required) {
  const auto it = j.find(key);
  if (it == j.end()) {
    if (required) throw ProtoError(key, "missing");
    return nullptr;
  }
  return &*it;
}

void read(const nlohmann::json& j, const char* key, double& out, const Limits& limits) {
  if (!j.is_number()) throw ProtoError(key, "expected a number");
  out = j.get<double>();
  if (!std::isfinite(out)) throw ProtoError(key, "not a finite number");
  if (limits.min && out < *limits.min)
    throw ProtoError(key, "below the minimum " + nlohmann::json(*limits.min).dump());
  if (limits.max && out > *limits.max)
    throw ProtoError(key, "above the maximum " + nlohmann::json(*limits.max).dump());
}

void read(const nlohmann::json& j, const char* key, std::int64_t& out, const Limits& limits) {
  if (!j.is_number_integer()) throw ProtoError(key, "expected an integer");
  out = j.get<std::int64_t>();
  if (limits.min && static_cast<double>(out) < *limits.min)
    throw ProtoError(key, "below the minimum");
  if (limits.max && static_cast<double>(out) > *limits.max)
    throw ProtoError(key, "above the maximum");
}

void read(const nlohmann::json& j, const char* key, bool& out, const Limits&) {
  if (!j.is_boolean()) throw ProtoError(key, "expected true or false");
  out = j.get<bool>();
}

void read(const nlohmann::json& j, const char* key, std::string& out, const Limits& limits) {
  if (!j.is_string()) throw ProtoError(key, "expected a string");
  out = j.get<std::string>();
  if (limits.min_length && out.size() < *limits.min_length) {
    throw ProtoError(key, "shorter than " + std::to_string(*limits.min_length) + " characters");
  }
  if (limits.max_length && out.size() > *limits.max_length) {
    throw ProtoError(key, "longer than " + std::to_string(*limits.max_length) + " characters");
  }
  if (limits.pattern != nullptr) {
    static thread_local std::unordered_map<const char*, std::regex> compiled;
    auto it = compiled.find(limits.pattern);
    if (it == compiled.end())
      it = compiled.emplace(limits.pattern, std::regex(limits.pattern)).first;
    if (!std::regex_match(out, it->second)) {
      throw ProtoError(key, std::string("does not match ") + limits.pattern);
    }
  }
}

void read(const nlohmann::json& j, const char* key, std::map<std::string, std::string>& out,
          const Limits& limits) {
  if (!j.is_object()) throw ProtoError(key, "expected an object of strings");
  if (limits.max_items && j.size() > *limits.max_items) {
    throw ProtoError(key, "more than " + std::to_string(*limits.max_items) + " entries");
  }
  static const std::regex kKey("^[a-z][A-Za-z0-9_]{0,63}$");
  out.clear();
  for (const auto& [k, v] : j.items()) {
    const std::string item = std::string(key) + "." + k;
    if (!std::regex_match(k, kKey))
      throw ProtoError(item, "keys are lower_snake_case with a unit suffix, e.g. temperature_C");
    if (!v.is_string() && !v.is_number()) throw ProtoError(item, "expected a string or a number");
    std::string value = v.is_string() ? v.get<std::string>() : v.dump();
    if (value.size() > 256 || value.find_first_of("\r\n") != std::string::npos) {
      throw ProtoError(item, "values are one line of at most 256 characters");
    }
    out[k] = std::move(value);
  }
}

}  // namespace detail
}  // namespace rig::proto
