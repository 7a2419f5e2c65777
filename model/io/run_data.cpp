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

std::optional<std::string> RunData::channel_length_mismatch() const {
  const auto values_for_samples = [this](const std::string& what,
                                         std::size_t values) -> std::optional<std::string> {
    if (values == size()) return std::nullopt;
    return what + " has " + std::to_string(values) + " values for " + std::to_string(size()) +
           " samples";
  };
  if (auto mismatch = values_for_samples("column 'x_mm'", x_mm.size())) return mismatch;
  if (auto mismatch = values_for_samples("column 'force_N'", force_N.size())) return mismatch;
  for (const auto& c : channels) {
    if (auto mismatch = values_for_samples("channel '" + c.name + "'", c.values.size()))
      return mismatch;
  }
  return std::nullopt;
}

std::string RunData::label() const {
  const auto eye = text("eye_id");
  return eye ? *eye : source;
}

}  // namespace rig::model
