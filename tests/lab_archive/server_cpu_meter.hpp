#pragma once
// CPU time of a PostgreSQL server: its postmaster and every process it started (backends,
// WAL writer, checkpointer), from /proc, so a benchmark can quote the server's CPU share.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rig::testing {

class ServerCpuMeter {
 public:
  explicit ServerCpuMeter(const std::string& data_dir) {
    std::ifstream pid_file(data_dir + "/postmaster.pid");
    pid_file >> postmaster_;
  }
  // User + system CPU seconds of the postmaster and its live children.
  double cpu_seconds() const {
    double total = 0.0;
    for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
      const std::string name = entry.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      long pid = 0, ppid = 0;
      double cpu = 0.0;
      if (!read_stat(entry.path() / "stat", pid, ppid, cpu)) continue;
      if (pid == postmaster_ || ppid == postmaster_) total += cpu;
    }
    return total;
  }

 private:
  static bool read_stat(const std::filesystem::path& path, long& pid, long& ppid, double& cpu) {
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto close = text.rfind(')');
    if (text.empty() || close == std::string::npos) return false;
    pid = std::stol(text);
    std::istringstream rest(text.substr(close + 2));
    std::string field;
    long utime = 0, stime = 0;
    for (int i = 3; rest >> field; ++i) {  // fields numbered as in proc(5)
      if (i == 4) ppid = std::stol(field);
      if (i == 14) utime = std::stol(field);
      if (i == 15) {
        stime = std::stol(field);
        break;
      }
    }
    cpu = static_cast<double>(utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
    return true;
  }
  long postmaster_ = -1;
};

}  // namespace rig::testing
