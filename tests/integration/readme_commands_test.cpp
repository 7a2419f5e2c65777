// Every command line of README.md and docs/technician-guide.md, run exactly as written (so a
// documented command cannot rot): `./rig ...` through the real script on this build tree
// (RIG_SKIP_SETUP, no packages or builds), `rig ...` as the built CLI, against a simulated
// rig this test starts (RIG_API, RIG_ARCHIVE; PORT in a command is rig-sim's port).
// Commands that run until Ctrl-C get one: `./rig demo` once it serves the overlay, benches
// and haptic playback after a bounded time (they must still be running or have ended well).
// Four are not run (`./rig test`, `./rig stress`, `./rig fuzz`, `./rig lint`: minutes to hours), each for a
// stated reason, and the test checks what it can of them.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "command.hpp"
#include "documented_commands.hpp"
#include "rig_processes.hpp"

namespace rig {
namespace {

using testing::DocumentedCommand;

struct Finished {
  int exit_code = -1;
  bool timed_out = false;  // still running at the bound: stopped with Ctrl-C (SIGINT)
  std::string out, err;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs `command` with sh in its own process group, as a terminal would. Ends it with Ctrl-C
// (SIGINT to the group) when `ready_text` shows on stderr or after `bound_s`.
Finished run_in_shell(const std::string& command, const std::string& dir, double bound_s, const std::string& ready_text = "") {
  const std::string out = dir + "/cmd.out", err = dir + "/cmd.err";
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    if (chdir(dir.c_str()) != 0) _exit(126);
    // exec: the command itself, not a shell waiting for it, gets the Ctrl-C and gives the status.
    execl("/bin/sh", "sh", "-c", ("exec " + command + " >" + out + " 2>" + err).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(pid, pid);
  Finished f;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(bound_s);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    const bool ready = !ready_text.empty() && slurp(err).find(ready_text) != std::string::npos;
    if (ready || std::chrono::steady_clock::now() > end) {
      f.timed_out = !ready;
      ::kill(-pid, SIGINT);
      for (int i = 0; i < 300 && waitpid(pid, &status, WNOHANG) == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
      ::kill(-pid, SIGKILL);
      waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  f.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  f.out = slurp(out);
  f.err = slurp(err);
  return f;
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

class DocumentedCommands : public ::testing::Test {
 protected:
  void SetUp() override {
    // ./rig looks for its release tree under RIG_BUILD_DIR: this build tree, as it is.
    std::filesystem::create_directories(dir_.file("build"));
    std::filesystem::create_symlink(std::filesystem::path(RIG_TEST_BIN_DIR).parent_path(), dir_.file("build/release"));
  }

  std::string environment() const {
    std::string env = "RIG_BUILD_DIR=" + dir_.file("build") + " RIG_SKIP_SETUP=1 PATH=" + std::string(RIG_TEST_BIN_DIR) + ":$PATH";
    if (rig_) env += " RIG_API=" + rig_->url() + " RIG_ARCHIVE=" + rig_->archive_path();
    return env;
  }

  // The command as a shell line: ./rig is the script of this checkout, PORT is rig-sim's.
  std::string shell_line(const std::string& text) const {
    std::string line = text;
    if (line.rfind("./rig", 0) == 0) line = testing::source("rig") + line.substr(5);
    const auto port = line.find(" PORT ");
    if (port != std::string::npos && rig_) line.replace(port, 6, " " + std::to_string(rig_->sim_port()) + " ");
    return "env " + environment() + " " + line;
  }

  void run_documented(const DocumentedCommand& c) {
    const std::vector<std::string> w = words(c.text);
    const std::string sub = w.size() > 1 ? w[1] : "";
    const std::string where = c.file + ":" + std::to_string(c.line) + ": " + c.text;
    std::printf("DOC-COMMAND | %s\n", where.c_str());
    if (w[0] == "./rig" && sub == "test") {
      // Not run: it is the run this test is part of (40 min). Its entry in the script is checked.
      EXPECT_EQ(testing::run_command("grep -q '^ *test) shift; cmd_test' " + testing::source("rig")).exit_code, 0) << where;
      return;
    }
    if (w[0] == "./rig" && sub == "stress") {
      // Not run: it is the load tier (about 30 min, label load). Its entry in the script is checked.
      EXPECT_EQ(testing::run_command("grep -q '^ *stress) shift; cmd_stress' " + testing::source("rig")).exit_code, 0) << where;
      return;
    }
    if (w[0] == "./rig" && sub == "fuzz") {
      // Not run: it builds a clang tree and fuzzes every target (minutes). Its entry is checked.
      EXPECT_EQ(testing::run_command("grep -q '^ *fuzz) shift; cmd_fuzz' " + testing::source("rig")).exit_code, 0) << where;
      EXPECT_EQ(testing::run_command("command -v clang++").exit_code, 0) << where;
      return;
    }
    if (w[0] == "./rig" && sub == "lint") {
      // Not run: it rebuilds the release tree and tidies every file (minutes). Its tools are checked.
      EXPECT_EQ(testing::run_command("command -v clang-format && command -v clang-tidy").exit_code, 0) << where;
      return;
    }
    const bool until_overlay = sub == "demo" && c.text.find("--once") == std::string::npos;
    const bool bounded = sub == "bench" || sub == "haptic";
    const Finished f = run_in_shell(shell_line(c.text), dir_.path().string(), until_overlay ? 300 : (bounded ? 4 : 240),
                                    until_overlay ? "live overlay at" : "");
    if (bounded && f.timed_out) return;  // ran its bounded time without failing
    EXPECT_FALSE(f.timed_out) << where << " did not finish\n" << f.err;
    EXPECT_EQ(f.exit_code, 0) << where << "\nstdout:\n" << f.out << "\nstderr:\n" << f.err;
    if (c.text.find("--format json") != std::string::npos) {
      EXPECT_TRUE(nlohmann::json::accept(f.out)) << where << " printed no JSON:\n" << f.out;
    }
  }

  void run_all_of(const std::string& document) {
    const auto commands = testing::documented_commands(testing::source(document), document);
    ASSERT_FALSE(commands.empty()) << document;
    rig_ = std::make_unique<testing::RigProcesses>(dir_);
    for (const auto& c : commands) run_documented(c);
  }

  testing::ScratchDir dir_{"documented-commands"};
  std::unique_ptr<testing::RigProcesses> rig_;
};

TEST(DocumentedCommandList, HoldsTheReadmesDemoLinesAndOneCommandPerLine) {
  const auto commands = testing::documented_commands(testing::source("README.md"), "README.md");
  std::set<std::string> texts;
  for (const auto& c : commands) {
    texts.insert(c.text);
    EXPECT_EQ(c.text.find(" | "), std::string::npos) << "not one command (a shell would pipe it): " << c.text;
  }
  EXPECT_TRUE(texts.count("./rig demo --once --format json")) << "the README's JSON demo line";
  EXPECT_TRUE(texts.count("./rig demo"));
  EXPECT_TRUE(texts.count("./rig home"));
}

TEST_F(DocumentedCommands, EveryCommandLineOfTheReadmeRunsAsWritten) { run_all_of("README.md"); }

TEST_F(DocumentedCommands, EveryCommandLineOfTheTechnicianGuideRunsAsWritten) { run_all_of("docs/technician-guide.md"); }

}  // namespace
}  // namespace rig
