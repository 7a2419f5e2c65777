// libFuzzer target: rigd's config reader (TOML + schema). Any file either loads or is
// refused with a ConfigError naming file, line and key; any other exception is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "rig/config/config_error.hpp"
#include "rig/config/rigd_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/rig-fuzz-config-" + std::to_string(::getpid()) + ".toml";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    (void)rig::config::load_rigd_config(path);
  } catch (const rig::config::ConfigError&) {
    // refused with file, line and key: fine
  }
  return 0;
}
