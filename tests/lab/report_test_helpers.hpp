#pragma once
// Reading a report back in the report tests: the file, its embedded data, series means.
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace rig::model {

inline double mean_of(const nlohmann::json& values) {
  double sum = 0.0;
  int n = 0;
  for (const auto& v : values) {
    if (v.is_null()) continue;
    sum += v.get<double>();
    ++n;
  }
  return n > 0 ? sum / n : NAN;
}

inline std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The report's data object, parsed back out of the HTML.
inline nlohmann::json embedded_data(const std::string& html) {
  const std::string marker = "const report = ";
  const auto at = html.find(marker);
  if (at == std::string::npos) return {};
  const auto end = html.find(";\n", at);
  return nlohmann::json::parse(html.substr(at + marker.size(), end - at - marker.size()));
}

}  // namespace rig::model
