#pragma once
// A supervised child process (rig-sim, rigd in the demo): started with its output in a log
// file, killed with the parent, stopped with SIGTERM then SIGKILL.
#include <sys/types.h>

#include <string>
#include <vector>

namespace rig::cli {

class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool running();
  void stop(int timeout_ms = 5000);  // SIGTERM, then SIGKILL after the time-out
  pid_t pid() const { return pid_; }
  const std::string& log_path() const { return log_path_; }
  // Waits until `text` appears in the log; returns the line holding it (throws on timeout
  // or if the child exits, quoting the end of its log).
  std::string wait_for_line(const std::string& text, int timeout_ms);
  std::string log_tail(std::size_t bytes = 2000) const;

 private:
  pid_t pid_ = -1;
  std::string log_path_;
  std::string name_;
};

}  // namespace rig::cli
