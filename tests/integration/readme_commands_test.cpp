// Every command line of README.md and docs/technician-guide.md, run exactly as written (so a
// documented command cannot rot): `./rig ...` through the real script on this build tree
// (RIG_SKIP_SETUP, no packages or builds), `rig ...` as the built CLI, against a simulated
// rig this test starts (RIG_API, RIG_ARCHIVE; PORT in a command is rig-sim's port).
// Commands that run until Ctrl-C get one: `./rig demo` once it serves the overlay, benches
// and haptic playback after a bounded time (they must still be running or have ended well).
// Three are not run (`./rig test`, `./rig stress`, `./rig fuzz`: minutes to hours) and one only in
// part (`./rig lint`: its source rules, not clang-tidy), each for a stated reason, and the test
// checks what it can of them.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "command.hpp"
#include "documented_commands.hpp"
#include "pg_test_server.hpp"
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

// Starts `command` with sh in `dir`, in its own process group as a terminal would, its output
// redirected as `redirect` says. exec: the command itself, not a shell waiting for it, gets
// the Ctrl-C and gives the status. The script is built before fork: no allocation in the child.
// Ctrl-C reaches it as a terminal's would: a test started in the background (ctest under a
// script's `&`) inherits SIGINT ignored, and a bench then ran on to the 30 s SIGKILL instead
// of stopping at its bound (8 benches, 240 s of the docs' test, 2026-12-02).
pid_t spawn_in_group(const std::string& command, const std::string& dir,
                     const std::string& redirect) {
  const std::string script = "exec " + command + " " + redirect;
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    signal(SIGINT, SIG_DFL);
    if (chdir(dir.c_str()) != 0) _exit(126);
    execl("/bin/sh", "sh", "-c", script.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(pid, pid);
  return pid;
}

// Runs `command` (spawn_in_group). Ends it with Ctrl-C (SIGINT to the group) when
// `ready_text` shows on stderr or after `bound_s`.
Finished run_in_shell(const std::string& command, const std::string& dir, double bound_s,
                      const std::string& ready_text = "") {
  const std::string out = dir + "/cmd.out", err = dir + "/cmd.err";
  const pid_t pid = spawn_in_group(command, dir, ">" + out + " 2>" + err);
  Finished f;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(bound_s);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    const bool ready = !ready_text.empty() && slurp(err).find(ready_text) != std::string::npos;
    if (ready || std::chrono::steady_clock::now() > end) {
      f.timed_out = !ready;
      ::kill(-pid, SIGINT);
      for (int i = 0; i < 300 && waitpid(pid, &status, WNOHANG) == 0; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
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

// A usage line, not a command: it shows placeholders (PATH..., [--with E1,E2], FILE, DIR).
bool is_synopsis(const std::vector<std::string>& w) {
  static const std::regex kPlaceholder(R"([A-Z]{3,}|.*\.\.\..*|\[.*)");
  for (std::size_t k = 1; k < w.size(); ++k) {
    if (w[k] != "PORT" && std::regex_match(w[k], kPlaceholder)) return true;
  }
  return false;
}

class DocumentedCommands : public ::testing::Test {
 protected:
  void SetUp() override {
    // ./rig looks for its release tree under RIG_BUILD_DIR: this build tree, as it is.
    std::filesystem::create_directories(dir_.file("build"));
    std::filesystem::create_symlink(std::filesystem::path(RIG_TEST_BIN_DIR).parent_path(),
                                    dir_.file("build/release"));
    // Commands run in the scratch folder as if it were the checkout (what they write stays
    // there): the checkout's model and config files are where the docs say they are.
    for (const char* folder : {"model", "config"})
      std::filesystem::create_symlink(testing::source(folder), dir_.file(folder));
  }

  std::string environment() const {
    std::string env = "RIG_BUILD_DIR=" + dir_.file("build") +
                      " RIG_SKIP_SETUP=1 PATH=" + std::string(RIG_TEST_BIN_DIR) + ":$PATH";
    if (rig_) env += " RIG_API=" + rig_->url() + " RIG_ARCHIVE=" + rig_->archive_path();
    if (pg_)
      env += " PGPORT=" +
             std::to_string(pg_->port());  // the docs' "host=localhost" on the test's server
    return env;
  }

  // The command as a shell line: ./rig is the script of this checkout, PORT is rig-sim's.
  std::string shell_line(const std::string& text) const {
    std::string line = text;
    if (line.rfind("./rig", 0) == 0) line = testing::source("rig") + line.substr(5);
    const auto port = line.find(" PORT ");
    if (port != std::string::npos && rig_)
      line.replace(port, 6, " " + std::to_string(rig_->sim_port()) + " ");
    // A rig's password file (docs/lab-archive.md makes it under /etc): the test's own copy.
    const std::string etc_password = "/etc/rigd/lab-archive.password";
    if (const auto at = line.find(etc_password); at != std::string::npos)
      line.replace(at, etc_password.size(), dir_.file("lab-archive.password"));
    return "env " + environment() + " " + line;
  }

  // Each line's wall time is printed after it (DOC-COMMAND-TIME): where the tier's time goes.
  void run_documented(const DocumentedCommand& c) {
    const auto start = std::chrono::steady_clock::now();
    run_one_documented(c);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("DOC-COMMAND-TIME | %.1f s | %s:%d\n", seconds, c.file.c_str(), c.line);
  }

  void run_one_documented(const DocumentedCommand& c) {
    const std::vector<std::string> w = words(c.text);
    const std::string sub = w.size() > 1 ? w[1] : "";
    const std::string where = c.file + ":" + std::to_string(c.line) + ": " + c.text;
    std::printf("DOC-COMMAND | %s\n", where.c_str());
    if (w[0] == "./rig" && sub == "test") {
      // Not run: it is the run this test is part of (40 min). Its entry in the script is checked.
      EXPECT_EQ(testing::run_command("grep -q '^ *test) shift; cmd_test' " + testing::source("rig"))
                    .exit_code,
                0)
          << where;
      return;
    }
    if (w[0] == "./rig" && sub == "stress") {
      // Not run: it is the load tier (about 30 min, label load). Its entry in the script is
      // checked.
      EXPECT_EQ(
          testing::run_command("grep -q '^ *stress) shift; cmd_stress' " + testing::source("rig"))
              .exit_code,
          0)
          << where;
      return;
    }
    if (w[0] == "./rig" && sub == "fuzz") {
      // Not run: it builds a clang tree and fuzzes every target (minutes). Its entry is checked.
      EXPECT_EQ(testing::run_command("grep -q '^ *fuzz) shift; cmd_fuzz' " + testing::source("rig"))
                    .exit_code,
                0)
          << where;
      EXPECT_EQ(testing::run_command("command -v clang++").exit_code, 0) << where;
      return;
    }
    if (w[0] == "./rig" && sub == "lint") {
      // Its source rules are run (clang-format over every C++ file, none over 600 lines: a
      // few seconds); clang-tidy is not (it builds its own tree and tidies every file: tens of
      // minutes), its tool is checked.
      const auto sources = testing::run_command(testing::source("rig") + " lint --sources-only");
      EXPECT_EQ(sources.exit_code, 0) << where << ": " << sources.output;
      EXPECT_EQ(testing::run_command("command -v clang-tidy").exit_code, 0) << where;
      return;
    }
    if (is_synopsis(w)) return check_synopsis(w, where);
    if (c.text.size() > 2 && c.text.compare(c.text.size() - 2, 2, " &") == 0)
      return start_in_background(c.text.substr(0, c.text.size() - 2), where);
    if (c.text.find("--device phantom") != std::string::npos) {
      // Needs a Phantom and OpenHaptics' libHD, which no test machine has: it must refuse
      // clearly and point to the simulated device.
      const Finished f = run_in_shell(shell_line(c.text), dir_.path().string(), 60);
      EXPECT_NE(f.exit_code, 0) << where;
      EXPECT_NE(f.err.find("--device sim"), std::string::npos) << where << "\n" << f.err;
      return;
    }
    const bool until_overlay = sub == "demo" && c.text.find("--once") == std::string::npos;
    // Benches and haptic sessions run for a bounded time, except one that writes what the
    // next line reads (--save-runs): 1 s, in which a bench refuses a wrong option or value
    // (it does in under 0.1 s; its figures are its own business, `./rig bench`). About 40 bench
    // lines at 2 s each were a fifth of the docs' tests, and the lab benches spin both cores. Any
    // other command must end within 480 s, a hang guard: a diagnose of nine runs (25 s quiet) ran
    // past 240 s under busy-machine (2026-12-02).
    const bool bounded =
        (sub == "bench" || sub == "haptic") && c.text.find("--save-runs") == std::string::npos;
    const Finished f = run_in_shell(shell_line(c.text), dir_.path().string(),
                                    until_overlay ? 300 : (bounded ? 1 : 480),
                                    until_overlay ? "live overlay at" : "");
    if (bounded && f.timed_out) return;  // ran its bounded time without failing
    EXPECT_FALSE(f.timed_out) << where << " did not finish\n" << f.err;
    EXPECT_EQ(f.exit_code, 0) << where << "\nstdout:\n" << f.out << "\nstderr:\n" << f.err;
    if (c.text.find("--format json") != std::string::npos) {
      EXPECT_TRUE(nlohmann::json::accept(f.out)) << where << " printed no JSON:\n" << f.out;
    }
  }

  // A usage line: its command's --help must list every option the line shows.
  void check_synopsis(const std::vector<std::string>& w, const std::string& where) {
    static const std::regex kWord("[a-z][a-z-]*");
    std::string command = w[0];
    for (std::size_t k = 1; k < w.size() && std::regex_match(w[k], kWord); ++k)
      command += " " + w[k];
    const Finished f = run_in_shell(shell_line(command + " --help"), dir_.path().string(), 60);
    ASSERT_EQ(f.exit_code, 0) << where << "\n" << f.err;
    static const std::regex kOption(R"(--[a-z][a-z-]*)");
    for (const std::string& word : w) {
      std::smatch option;
      if (std::regex_search(word, option, kOption)) {
        EXPECT_NE(f.out.find(option.str()), std::string::npos)
            << where << ": `" << command << " --help` has no " << option.str();
      }
    }
  }

  // A line ending in `&` starts what the next lines use (a socat pty pair, rig-sim on it): it
  // runs in the background until the document ends, and is ready once it printed its first
  // line or made the `link=` paths it names.
  void start_in_background(const std::string& text, const std::string& where) {
    const std::string log = dir_.file("background-" + std::to_string(background_.size()) + ".log");
    const pid_t pid = spawn_in_group(shell_line(text), dir_.path().string(), ">" + log + " 2>&1");
    background_.push_back(pid);
    std::vector<std::string> links;
    static const std::regex kLink(R"(link=\$PWD/([A-Za-z0-9_.-]+))");
    for (std::sregex_iterator it(text.begin(), text.end(), kLink), end; it != end; ++it)
      links.push_back(dir_.file((*it)[1]));
    for (int i = 0; i < 300; ++i) {
      bool ready = links.empty() ? !slurp(log).empty() : true;
      for (const std::string& link : links) ready = ready && std::filesystem::exists(link);
      int status = 0;
      ASSERT_EQ(waitpid(pid, &status, WNOHANG), 0) << where << " ended at once:\n" << slurp(log);
      if (ready) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    FAIL() << where << " was not ready within 30 s:\n" << slurp(log);
  }

  void stop_background() {
    for (const pid_t pid : background_) {
      ::kill(-pid, SIGINT);
      for (int i = 0; i < 50 && waitpid(pid, nullptr, WNOHANG) == 0; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      ::kill(-pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
    background_.clear();
  }

  void run_all_of(const std::string& document, const std::string& also = "") {
    const auto commands = testing::documented_commands(testing::source(document), document, also);
    ASSERT_FALSE(commands.empty()) << document;
    if (!rig_) rig_ = std::make_unique<testing::RigProcesses>(dir_);
    for (const auto& c : commands) run_documented(c);
    stop_background();
  }

  void TearDown() override { stop_background(); }

  testing::ScratchDir dir_{"documented-commands"};
  std::unique_ptr<testing::RigProcesses> rig_;
  std::unique_ptr<testing::PgTestServer> pg_;
  std::vector<pid_t> background_;
};

TEST(DocumentedCommandList, HoldsTheReadmesDemoLinesAndOneCommandPerLine) {
  const auto commands = testing::documented_commands(testing::source("README.md"), "README.md");
  std::set<std::string> texts;
  for (const auto& c : commands) {
    texts.insert(c.text);
    EXPECT_EQ(c.text.find(" | "), std::string::npos)
        << "not one command (a shell would pipe it): " << c.text;
  }
  EXPECT_TRUE(texts.count("./rig demo --once --format json")) << "the README's JSON demo line";
  EXPECT_TRUE(texts.count("./rig demo"));
  EXPECT_TRUE(texts.count("./rig home"));
}

TEST_F(DocumentedCommands, EveryCommandLineOfTheReadmeRunsAsWritten) {
  run_all_of("README.md");
}

TEST_F(DocumentedCommands, EveryCommandLineOfTheTechnicianGuideRunsAsWritten) {
  run_all_of("docs/technician-guide.md");
}

// The other documents, in file order, against what they assume is there: a rig with three
// runs in its archive (docs/haptics.md plays run 3), and a lab's PostgreSQL at localhost set
// up with the SQL of docs/lab-archive.md (a throwaway server; PGPORT points libpq at it).
// What docs/ write under /tmp is removed first, so each run starts from nothing.
TEST_F(DocumentedCommands, EveryCommandLineOfTheOtherDocsRunsAsWrittenOrShowsItsOptionsInHelp) {
  for (const char* path : {"/tmp/lab-demo.sqlite", "/tmp/lab-demo-runs", "/tmp/lab-export",
                           "/tmp/zoo-draws", "/tmp/runs", "/tmp/fit.html"}) {
    std::filesystem::remove_all(path);
  }
  pg_ = std::make_unique<testing::PgTestServer>();
  static const std::regex kSql(
      R"re(runuser -u postgres -- psql -c "(CREATE ROLE [^"]*|GRANT [^"]*)")re");
  int statements = 0;
  std::ifstream lab_doc(testing::source("docs/lab-archive.md"));
  for (std::string line; std::getline(lab_doc, line);) {
    std::smatch sql;
    if (std::regex_search(line, sql, kSql)) pg_->psql("postgres", sql[1].str()), ++statements;
  }
  ASSERT_EQ(statements, 3) << "docs/lab-archive.md: the two roles and the reader's grant";
  pg_->psql("postgres",
            "ALTER DATABASE lab OWNER TO rig_writer");  // the doc's `createdb -O rig_writer lab`
  std::ofstream(dir_.file("lab-archive.password")) << "change-me-writer\n";
  std::filesystem::permissions(
      dir_.file("lab-archive.password"),
      std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  rig_ = std::make_unique<testing::RigProcesses>(dir_);
  const std::string rig = testing::bin("rig"), runs = dir_.file("runs");
  ASSERT_EQ(testing::run_command(rig + " sim generate --out " + runs +
                                 " --iops 15,16,17 --velocities 2 --depth 6")
                .exit_code,
            0);
  std::string files;
  for (const auto& f : std::filesystem::directory_iterator(runs)) files += " " + f.path().string();
  const auto imported =
      testing::run_command(rig + " --archive " + rig_->archive_path() + " import" + files);
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  std::vector<std::string> documents;
  for (const auto& f : std::filesystem::directory_iterator(testing::source("docs"))) {
    if (f.path().extension() == ".md" && f.path().filename() != "technician-guide.md")
      documents.push_back("docs/" + f.path().filename().string());
  }
  std::sort(documents.begin(), documents.end());
  for (const std::string& document : documents) {
    if (!testing::documented_commands(testing::source(document), document, "socat|mkdir").empty())
      run_all_of(document, "socat|mkdir");
  }
}

}  // namespace
}  // namespace rig
