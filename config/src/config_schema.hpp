#pragma once
// The declared keys of rigd's configuration: type, allowed range or choices, and a
// one-line description with the unit.
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "rig/config/rigd_config.hpp"

namespace rig::config {

using ConfigValue = std::variant<std::int64_t, double, bool, std::string>;

struct ConfigField {
  enum class Type { kInteger, kNumber, kBoolean, kString };
  std::string key;
  Type type = Type::kNumber;
  double min = 0.0;
  double max = 0.0;
  std::vector<std::string> choices;  // strings: allowed values (empty = any)
  std::string doc;
  std::function<void(RigdConfig&, const ConfigValue&)> assign;
  bool is_path = false;  // relative paths resolve against the config file's directory
};

const std::vector<ConfigField>& config_fields();
// [lab_archive] (lab_archive_fields.cpp).
void add_lab_archive_fields(std::vector<ConfigField>& fields);
void check_lab_archive(const LabArchiveSection& lab,
                       const std::function<void(const std::string&)>& fail);

}  // namespace rig::config
