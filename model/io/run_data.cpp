#include "run_data.hpp"

#include <charconv>
#include <cmath>

namespace rig::model {

std::optional<std::string> RunData::text(const std::string& key) const {
  for (const auto& [k, v] : meta) {
    if (k == key) return v;
  }
  return std::nullopt;
}

std::optional<double> RunData::number(const std::string& key) const {
  const auto value = text(key);
  if (!value || value->empty()) return std::nullopt;
  double parsed = 0.0;
  const char* end = value->data() + value->size();
  const auto result = std::from_chars(value->data(), end, parsed);
  if (result.ec != std::errc{} || result.ptr != end || !std::isfinite(parsed)) return std::nullopt;
  return parsed;
}

void RunData::set(const std::string& key, const std::string& value) {
  for (auto& [k, v] : meta) {
    if (k == key) {
      v = value;
      return;
    }
  }
  meta.emplace_back(key, value);
}

const Channel* RunData::channel(const std::string& name) const {
  for (const auto& c : channels) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::string RunData::label() const {
  const auto eye = text("eye_id");
  return eye ? *eye : source;
}

}  // namespace rig::model
