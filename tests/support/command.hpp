#pragma once
// Runs a shell command for a test and keeps its output and exit code.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace rig::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout, and stderr too when asked for
};

inline CommandResult run_command(const std::string& command, bool with_stderr = true) {
  std::array<char, 4096> buffer{};
  CommandResult result;
  FILE* pipe = popen((command + (with_stderr ? " 2>&1" : " 2>/dev/null")).c_str(), "r");
  if (pipe == nullptr) return result;
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) result.output += buffer.data();
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace rig::testing
