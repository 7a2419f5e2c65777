#pragma once
// Checked readers used by the generated message code: each names the field at fault.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rig/proto/messages.hpp"

namespace rig::proto::detail {

struct Limits {
  std::optional<double> min;
  std::optional<double> max;
  std::optional<std::size_t> min_length;
  std::optional<std::size_t> max_length;
  std::optional<std::size_t> max_items;
  const char* pattern = nullptr;
};

void require_object(const nlohmann::json& j, const char* message);
void reject_unknown(const nlohmann::json& j, std::initializer_list<const char*> known);
const nlohmann::json* field(const nlohmann::json& j, const char* key, bool required);

void read(const nlohmann::json& j, const char* key, double& out, const Limits& limits);
void read(const nlohmann::json& j, const char* key, std::int64_t& out, const Limits& limits);
void read(const nlohmann::json& j, const char* key, bool& out, const Limits& limits);
void read(const nlohmann::json& j, const char* key, std::string& out, const Limits& limits);
void read(const nlohmann::json& j, const char* key, std::map<std::string, std::string>& out,
          const Limits& limits);

template <typename T>
void read(const nlohmann::json& j, const char* key, std::vector<T>& out, const Limits& limits) {
  if (!j.is_array()) throw ProtoError(key, "expected an array");
  if (limits.max_items && j.size() > *limits.max_items) {
    throw ProtoError(key, "more than " + std::to_string(*limits.max_items) + " items");
  }
  out.clear();
  out.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string item_key = std::string(key) + "[" + std::to_string(i) + "]";
    T value{};
    read(j[i], item_key.c_str(), value, Limits{});
    out.push_back(std::move(value));
  }
}

// Nested message: the nested error's field gets this field as prefix.
template <typename T>
void read(const nlohmann::json& j, const char* key, T& out, const Limits&) {
  try {
    from_json(j, out);
  } catch (const ProtoError& e) {
    throw ProtoError(std::string(key) + (e.field().empty() ? "" : "." + e.field()), e.reason());
  }
}

template <typename T>
void read_field(const nlohmann::json& j, const char* key, T& out, const Limits& limits) {
  if (const nlohmann::json* value = field(j, key, true)) read(*value, key, out, limits);
}

template <typename T>
void read_field(const nlohmann::json& j, const char* key, std::optional<T>& out,
                const Limits& limits) {
  const nlohmann::json* value = field(j, key, false);
  if (value == nullptr || value->is_null()) {
    out.reset();
    return;
  }
  out.emplace();
  read(*value, key, *out, limits);
}

}  // namespace rig::proto::detail
