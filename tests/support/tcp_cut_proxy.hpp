#pragma once
// A loopback TCP proxy the test controls: forwards to a target port until cut(); then it
// drops every open connection and refuses new ones (reset) until restore(). Stands for a
// network cut between a rig and the lab's server.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace rig::testing {

class TcpCutProxy {
 public:
  explicit TcpCutProxy(int target_port) : target_port_(target_port) {
    listen_fd_ = socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in addr = loopback(0);
    socklen_t length = sizeof addr;
    if (bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        listen(listen_fd_, 64) != 0 ||
        getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &length) != 0) {
      throw std::runtime_error("TcpCutProxy: cannot listen");
    }
    port_ = ntohs(addr.sin_port);
    thread_ = std::thread([this] { loop(); });
  }
  ~TcpCutProxy() {
    stop_ = true;
    thread_.join();
    close_all();
    close(listen_fd_);
  }
  TcpCutProxy(const TcpCutProxy&) = delete;
  TcpCutProxy& operator=(const TcpCutProxy&) = delete;

  int port() const { return port_; }
  // Returns once every open connection is reset: nothing is forwarded after cut() returns.
  void cut() {
    cut_applied_ = false;
    cut_ = true;
    while (!cut_applied_) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  void restore() { cut_ = false; }

 private:
  static sockaddr_in loopback(int port) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    return addr;
  }
  static void reset_and_close(int fd) {
    const linger hard{1, 0};  // RST, as a dead route would eventually give
    setsockopt(fd, SOL_SOCKET, SO_LINGER, &hard, sizeof hard);
    close(fd);
  }
  void close_all() {
    for (auto [a, b] : pairs_) {
      reset_and_close(a);
      reset_and_close(b);
    }
    pairs_.clear();
  }
  void accept_one() {
    const int client = accept(listen_fd_, nullptr, nullptr);
    if (client < 0) return;
    if (cut_) return reset_and_close(client);
    const int server = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr = loopback(target_port_);
    if (connect(server, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      reset_and_close(client);
      close(server);
      return;
    }
    pairs_.emplace_back(client, server);
  }
  // Copies what is readable on `from` to `to`; false when either side is gone.
  static bool pump(int from, int to) {
    char buffer[65536];
    const ssize_t n = read(from, buffer, sizeof buffer);
    if (n <= 0) return false;
    for (ssize_t sent = 0; sent < n;) {
      const ssize_t m = write(to, buffer + sent, static_cast<std::size_t>(n - sent));
      if (m <= 0) return false;
      sent += m;
    }
    return true;
  }
  void loop() {
    while (!stop_) {
      if (cut_) {
        close_all();
        cut_applied_ = true;
      }
      std::vector<pollfd> fds{{listen_fd_, POLLIN, 0}};
      for (auto [a, b] : pairs_) {
        fds.push_back({a, POLLIN, 0});
        fds.push_back({b, POLLIN, 0});
      }
      if (poll(fds.data(), fds.size(), 50) <= 0 || cut_)
        continue;  // cut while polling: forward nothing more
      std::vector<std::pair<int, int>> alive;
      for (std::size_t i = 0; i < pairs_.size(); ++i) {
        auto [a, b] = pairs_[i];
        bool ok = true;
        if ((fds[1 + 2 * i].revents & (POLLIN | POLLHUP | POLLERR)) != 0) ok = pump(a, b);
        if (ok && (fds[2 + 2 * i].revents & (POLLIN | POLLHUP | POLLERR)) != 0) ok = pump(b, a);
        if (ok) {
          alive.emplace_back(a, b);
        } else {
          close(a);
          close(b);
        }
      }
      pairs_.swap(alive);
      if ((fds[0].revents & POLLIN) != 0) accept_one();
    }
  }

  int target_port_;
  int listen_fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<bool> cut_{false};
  std::atomic<bool> cut_applied_{false};
  std::vector<std::pair<int, int>> pairs_;  // (client, server), touched only by the loop thread
  std::thread thread_;
};

}  // namespace rig::testing
