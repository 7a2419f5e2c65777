#pragma once
// What the VM's scenario script tells a kernel-tier test: environment variables naming the
// kernel objects it created (chip, sysfs directory, video node, gadget directory).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace rig::kernel_tests {

inline std::string env_or_empty(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr ? v : "";
}

// Writes one sysfs/configfs attribute; returns whether the kernel accepted it.
inline bool write_attribute(const std::string& path, const std::string& value) {
  std::ofstream out(path);
  out << value;
  out.flush();
  return out.good();
}

inline std::string read_attribute(const std::string& path) {
  std::ifstream in(path);
  std::string value;
  std::getline(in, value);
  return value;
}

}  // namespace rig::kernel_tests
