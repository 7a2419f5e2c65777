#pragma once
// A throwaway PostgreSQL 15 for tests and benchmarks: initdb in a temp dir, pg_ctl on a free
// loopback port, torn down (and deleted) by the destructor. initdb refuses to run as root,
// so as root the cluster belongs to `nobody` and every server command runs through runuser.
#include <netinet/in.h>
#include <pwd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "command.hpp"

namespace rig::testing {

class PgTestServer {
 public:
  static constexpr const char* kBin = "/usr/lib/postgresql/15/bin";

  // durable: fsync as a real server (benchmarks); tests skip it (a crash of the test
  // machine is not what they test, and fsync on a busy VM costs seconds).
  explicit PgTestServer(bool durable = false) : durable_(durable) {
    char pattern[] = "/tmp/rig-pg-XXXXXX";
    if (mkdtemp(pattern) == nullptr) throw std::runtime_error("mkdtemp failed");
    dir_ = pattern;
    if (geteuid() == 0) {
      const passwd* nobody = getpwnam("nobody");
      if (nobody == nullptr || chown(dir_.c_str(), nobody->pw_uid, nobody->pw_gid) != 0) {
        throw std::runtime_error("cannot give " + dir_ + " to user nobody");
      }
      as_user_ = "runuser -u nobody -- ";
    }
    port_ = free_port();
    copy_template_cluster();
    start();
    psql("postgres", "CREATE DATABASE lab");
  }
  ~PgTestServer() {
    run_command(as_user_ + kBin + std::string("/pg_ctl -D ") + dir_ + "/data -m immediate -w stop");
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  PgTestServer(const PgTestServer&) = delete;
  PgTestServer& operator=(const PgTestServer&) = delete;

  void start() {
    server("pg_ctl -D " + dir_ + "/data -l " + dir_ + "/log -w -t 30 -o \"-p " +
           std::to_string(port_) + " -k " + dir_ +
           " -c listen_addresses=127.0.0.1 -c max_connections=60" +
           (durable_ ? "" : " -c fsync=off") + "\" start");
  }
  // mode: fast (clean shutdown) or immediate (like a crash; WAL replay at the next start).
  void stop(const std::string& mode = "fast") {
    server("pg_ctl -D " + dir_ + "/data -m " + mode + " -w stop");
  }
  int port() const { return port_; }
  std::string conninfo(int port = 0) const {
    return "host=127.0.0.1 port=" + std::to_string(port == 0 ? port_ : port) +
           " user=postgres dbname=lab";
  }
  // One psql command against database db; its output (unaligned, tuples only).
  std::string psql(const std::string& db, const std::string& sql) const {
    const std::string escaped = shell_quote(sql);
    const auto r =
        run_command(std::string(kBin) + "/psql -X -q -At -v ON_ERROR_STOP=1 -h 127.0.0.1 -p " +
                    std::to_string(port_) + " -U postgres -d " + db + " -c " + escaped);
    if (r.exit_code != 0) throw std::runtime_error("psql failed: " + sql + "\n" + r.output);
    return r.output;
  }
  std::string query(const std::string& sql) const {
    std::string out = psql("lab", sql);
    while (!out.empty() && out.back() == '\n') out.pop_back();
    return out;
  }
  const std::string& dir() const { return dir_; }

  static int free_port() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof addr;
    if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length) != 0) {
      close(fd);
      throw std::runtime_error("no free port");
    }
    close(fd);
    return ntohs(addr.sin_port);
  }

 private:
  // initdb takes ~2 s; a cluster made once per machine (and user) and copied takes ~0.2 s.
  // Made under a temp name and renamed, so tests starting together never see half of one.
  void copy_template_cluster() {
    const std::string owner = as_user_.empty() ? std::to_string(geteuid()) : "nobody";
    const std::string templ = "/tmp/rig-pg15-template-" + owner;
    if (!std::filesystem::exists(templ + "/PG_VERSION")) {
      server("initdb -D " + dir_ + "/data -U postgres -A trust --no-sync -E UTF8 --locale=C");
      run_command(as_user_ + "cp -a " + dir_ + "/data " + dir_ + "/template && " + as_user_ +
                  "mv -T " + dir_ + "/template " + templ);
      return;
    }
    const auto r = run_command(as_user_ + "cp -a " + templ + " " + dir_ + "/data");
    if (r.exit_code != 0)
      throw std::runtime_error("cannot copy the template cluster " + templ + ": " + r.output);
  }
  static std::string shell_quote(const std::string& text) {
    std::string out = "'";
    for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
  }
  void server(const std::string& command) const {
    const auto r = run_command(as_user_ + kBin + "/" + command);
    if (r.exit_code != 0) {
      const auto log = run_command("tail -n 20 " + dir_ + "/log");
      throw std::runtime_error("PostgreSQL test server: '" + command + "' failed:\n" + r.output +
                               log.output);
    }
  }

  std::string dir_;
  std::string as_user_;
  int port_ = 0;
  bool durable_ = false;
};

}  // namespace rig::testing
