#pragma once
// Hostile and careless clients of rigd's API for the safety tests: idle connections (connect,
// never send) and slow-loris ones (headers trickling in, never finished).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "loopback_connect.hpp"

namespace rig::testing {

// Connections that hold a slot without ever finishing a request. Slow-loris ones send a
// request line and then one header byte every `trickle_ms` from a thread of their own.
class SilentClients {
 public:
  explicit SilentClients(int port, int trickle_ms = 100) : port_(port), trickle_ms_(trickle_ms) {
    trickler_ = std::thread([this] { trickle(); });
  }
  ~SilentClients() {
    running_ = false;
    trickler_.join();
  }
  void open_idle(const std::string& source, int count) {
    for (int i = 0; i < count; ++i) add(connect_from(io_, source, port_), false);
  }
  void open_slow_loris(const std::string& source, int count) {
    static const std::string kStart = "GET /api/status HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
    for (int i = 0; i < count; ++i) {
      auto socket = connect_from(io_, source, port_);
      ::send(socket->native_handle(), kStart.data(), kStart.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      add(std::move(socket), true);
    }
  }
  // How many of the first `first` connections opened (or of all, first < 0) the server closed.
  int closed_by_server_count(int first = -1) {
    std::lock_guard lock(mutex_);
    const std::size_t n =
        first < 0 ? sockets_.size()
                  : std::min<std::size_t>(sockets_.size(), static_cast<std::size_t>(first));
    int closed = 0;
    for (std::size_t i = 0; i < n; ++i) closed += closed_by_server(*sockets_[i].socket) ? 1 : 0;
    return closed;
  }
  bool newest_closed_by_server() {
    std::lock_guard lock(mutex_);
    return !sockets_.empty() && closed_by_server(*sockets_.back().socket);
  }
  void close_oldest() {
    std::lock_guard lock(mutex_);
    if (!sockets_.empty()) sockets_.pop_front();
  }
  int count() {
    std::lock_guard lock(mutex_);
    return static_cast<int>(sockets_.size());
  }

 private:
  struct Held {
    std::unique_ptr<boost::asio::ip::tcp::socket> socket;
    bool slow_loris;
  };
  void add(std::unique_ptr<boost::asio::ip::tcp::socket> socket, bool slow_loris) {
    std::lock_guard lock(mutex_);
    sockets_.push_back({std::move(socket), slow_loris});
  }
  void trickle() {
    while (running_) {
      {
        std::lock_guard lock(mutex_);
        for (auto& held : sockets_) {
          if (held.slow_loris)
            ::send(held.socket->native_handle(), "a", 1, MSG_NOSIGNAL | MSG_DONTWAIT);
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(trickle_ms_));
    }
  }

  boost::asio::io_context io_;
  int port_;
  int trickle_ms_;
  std::mutex mutex_;
  std::deque<Held> sockets_;
  std::atomic<bool> running_{true};
  std::thread trickler_;
};

}  // namespace rig::testing
