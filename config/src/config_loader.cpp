// Reads rigd's TOML config against the declared schema (config_schema.cpp).
#include <arpa/inet.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "config_schema.hpp"
#include "rig/config/config_error.hpp"
#include "rig/config/rigd_config.hpp"

namespace rig::config {
namespace {

const ConfigField* find_field(const std::string& key) {
  for (const auto& field : config_fields()) {
    if (field.key == key) return &field;
  }
  return nullptr;
}

std::string where(const std::string& origin, const toml::node& node) {
  const auto line = node.source().begin.line;
  return line > 0 ? origin + ":" + std::to_string(line) : origin;
}

std::string type_name(ConfigField::Type type) {
  switch (type) {
    case ConfigField::Type::kInteger:
      return "an integer";
    case ConfigField::Type::kNumber:
      return "a number";
    case ConfigField::Type::kBoolean:
      return "true or false";
    case ConfigField::Type::kString:
      return "a string";
  }
  return "?";
}

std::string format_number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

ConfigValue convert(const ConfigField& field, const toml::node& node, const std::string& at) {
  const std::string prefix = at + ": key '" + field.key + "': ";
  auto range_check = [&](double value) {
    if (!std::isfinite(value) || value < field.min || value > field.max) {
      throw ConfigError(prefix + format_number(value) + " is out of range [" +
                        format_number(field.min) + ", " + format_number(field.max) + "]");
    }
  };
  switch (field.type) {
    case ConfigField::Type::kInteger:
      if (!node.is_integer()) throw ConfigError(prefix + "expected " + type_name(field.type));
      range_check(static_cast<double>(*node.value<std::int64_t>()));
      return *node.value<std::int64_t>();
    case ConfigField::Type::kNumber:
      if (!node.is_number()) throw ConfigError(prefix + "expected " + type_name(field.type));
      range_check(*node.value<double>());
      return *node.value<double>();
    case ConfigField::Type::kBoolean:
      if (!node.is_boolean()) throw ConfigError(prefix + "expected " + type_name(field.type));
      return *node.value<bool>();
    case ConfigField::Type::kString: {
      if (!node.is_string()) throw ConfigError(prefix + "expected " + type_name(field.type));
      std::string value = *node.value<std::string>();
      if (!field.choices.empty() &&
          std::find(field.choices.begin(), field.choices.end(), value) == field.choices.end()) {
        std::string allowed;
        for (const auto& c : field.choices) allowed += (allowed.empty() ? "" : ", ") + c;
        throw ConfigError(prefix + "'" + value + "' is not one of: " + allowed);
      }
      return value;
    }
  }
  throw ConfigError(prefix + "unsupported type");
}

ConfigValue resolve(const ConfigField& field, ConfigValue value,
                    const std::filesystem::path& base) {
  if (!field.is_path) return value;
  const std::string& text = std::get<std::string>(value);
  if (text.empty() || std::filesystem::path(text).is_absolute()) return value;
  return (base / text).lexically_normal().string();
}

void apply_table(RigdConfig& config, const toml::table& table, const std::string& prefix,
                 const std::string& origin, const std::filesystem::path& base) {
  for (auto&& [name, node] : table) {
    const std::string key =
        prefix.empty() ? std::string(name.str()) : prefix + "." + std::string(name.str());
    if (const toml::table* child = node.as_table()) {
      apply_table(config, *child, key, origin, base);
      continue;
    }
    const ConfigField* field = find_field(key);
    if (field == nullptr) throw ConfigError(where(origin, node) + ": unknown key '" + key + "'");
    field->assign(config, resolve(*field, convert(*field, node, where(origin, node)), base));
  }
}

std::uint64_t fnv1a(const std::string& text, std::uint64_t hash = 14695981039346656037ULL) {
  for (const unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ULL;
  }
  return hash;
}

// rigd binds to an address, not a name: "localhost" may resolve to ::1, 127.0.0.1 or both.
template <typename Fail>
void check_bind_address(const std::string& bind, Fail fail) {
  unsigned char buffer[16];
  if (inet_pton(AF_INET, bind.c_str(), buffer) == 1 ||
      inet_pton(AF_INET6, bind.c_str(), buffer) == 1)
    return;
  fail("key 'api.bind' = \"" + bind +
       "\" is not an IP address (use \"127.0.0.1\" for loopback, \"0.0.0.0\" for every interface)");
}

template <typename Fail>
void check_allowed_origins(const std::string& list, Fail fail) {
  std::istringstream items(list);
  std::string item;
  while (std::getline(items, item, ',')) {
    const auto first = item.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    const std::string origin = item.substr(first, item.find_last_not_of(" \t") - first + 1);
    if (origin.rfind("http://", 0) != 0 && origin.rfind("https://", 0) != 0) {
      fail("key 'api.allowed_origins': '" + origin + "' is not an origin like http://host:port");
    }
  }
}

void check_consistency(const RigdConfig& c, const std::string& origin) {
  const rt::MotionSettings& m = c.loop.motion;
  auto fail = [&](const std::string& what) { throw ConfigError(origin + ": " + what); };
  if (!(m.soft_min_mm < m.park_mm && m.park_mm < m.surface_mm && m.surface_mm < m.soft_max_mm)) {
    fail(
        "keys 'motion.soft_min_mm' < 'motion.park_mm' < 'motion.surface_mm' < 'motion.soft_max_mm' "
        "must hold");
  }
  if (m.min_velocity_mm_s > m.max_velocity_mm_s)
    fail("key 'motion.min_velocity_mm_s' exceeds 'motion.max_velocity_mm_s'");
  if (c.loop.iop.min_mmHg > c.loop.iop.max_mmHg) fail("key 'iop.min_mmHg' exceeds 'iop.max_mmHg'");
  const double period_us = 1e6 / c.loop.rate_hz;
  if (c.daq.kind == "modbus" && c.daq.modbus.response_timeout_us >= period_us) {
    fail("key 'daq.response_timeout_us' (" + std::to_string(c.daq.modbus.response_timeout_us) +
         " us) must be below one loop period (" + format_number(period_us) + " us)");
  }
  // rigd judges lost writes itself before the DAQ's watchdog stops the motor for it.
  const int failed_writes = c.loop.safety.max_failed_writes;
  if (c.daq.kind == "modbus" && failed_writes * period_us >= c.daq.modbus.watchdog_ms * 1e3) {
    fail("key 'safety.max_failed_writes' (" + std::to_string(failed_writes) +
         " loop periods) must be shorter than 'daq.watchdog_ms' (" +
         std::to_string(c.daq.modbus.watchdog_ms) + " ms)");
  }
  if (c.archive.recorder_priority > 0 && c.archive.recorder_priority >= c.thread.priority &&
      c.thread.priority > 0) {
    fail("key 'archive.recorder_priority' (" + std::to_string(c.archive.recorder_priority) +
         ") must be below 'loop.priority' (" + std::to_string(c.thread.priority) +
         "): the loop comes first");
  }
  if (c.daq.modbus.transport == "rtu" && c.daq.modbus.serial_device.empty()) {
    fail("key 'daq.serial_device' is required for daq.transport = \"rtu\"");
  }
  check_allowed_origins(c.api.allowed_origins, fail);
  check_bind_address(c.api.bind, fail);
  check_lab_archive(c.lab_archive, fail);
  const bool loopback = c.api.bind == "127.0.0.1" || c.api.bind == "::1";
  if (!loopback && c.api.token_file.empty()) {
    fail("key 'api.bind' = \"" + c.api.bind + "\" is not loopback: 'api.token_file' is required");
  }
}

}  // namespace

RigdConfig load_rigd_config(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ConfigError(path + ": cannot open the config file");
  std::stringstream content;
  content << file.rdbuf();
  RigdConfig config;
  config.source_path = path;
  try {
    const toml::table table = toml::parse(content.str(), path);
    apply_table(config, table, "", path, std::filesystem::absolute(path).parent_path());
  } catch (const toml::parse_error& e) {
    throw ConfigError(path + ":" + std::to_string(e.source().begin.line) + ": " +
                      std::string(e.description()));
  }
  std::uint64_t hash = fnv1a(content.str());
  for (const auto& item : overrides) {
    const auto eq = item.find('=');
    const std::string origin = "--set " + item;
    if (eq == std::string::npos) throw ConfigError(origin + ": expected key=value");
    try {
      const std::string key = item.substr(0, eq);
      const toml::table table = toml::parse("v = " + item.substr(eq + 1), origin);
      const ConfigField* field = find_field(key);
      if (field == nullptr) throw ConfigError(origin + ": unknown key '" + key + "'");
      field->assign(config, resolve(*field, convert(*field, *table.get("v"), origin),
                                    std::filesystem::current_path()));
    } catch (const toml::parse_error& e) {
      throw ConfigError(origin + ": " + std::string(e.description()));
    }
    hash = fnv1a(item, hash);
  }
  check_consistency(config, path);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  config.hash = hex;
  return config;
}

std::string describe_config_keys() {
  std::ostringstream out;
  for (const auto& f : config_fields()) {
    out << f.key << " (" << type_name(f.type);
    if (f.type == ConfigField::Type::kInteger || f.type == ConfigField::Type::kNumber) {
      out << " in [" << format_number(f.min) << ", " << format_number(f.max) << "]";
    }
    if (!f.choices.empty()) {
      out << ":";
      for (const auto& c : f.choices) out << " " << c;
    }
    out << "): " << f.doc << "\n";
  }
  return out.str();
}

}  // namespace rig::config
