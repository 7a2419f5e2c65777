#include "sim_phantom.hpp"

#include <pthread.h>
#include <sched.h>

#include <cmath>
#include <ctime>
#include <numbers>

namespace rig::drivers {

SimPhantom::SimPhantom(const SimPhantomSettings& settings, const VirtualHand& hand)
    : s_(settings),
      hand_(&hand),
      pending_(static_cast<std::size_t>(std::max(settings.latency_ticks, 0)) + 1, 0.0) {
  felt_.reserve(static_cast<std::size_t>(hand.duration_s() * settings.rate_hz) +
                16);  // no allocation while running
}

SimPhantom::~SimPhantom() {
  stop();
}

double SimPhantom::output_latency_s() const noexcept {
  // The latency line plus the first-order amplifier's time constant.
  return s_.latency_ticks / s_.rate_hz + 1.0 / (2.0 * std::numbers::pi * s_.force_bandwidth_hz);
}

void SimPhantom::start(HapticServo& servo) {
  servo_ = &servo;
  running_.store(true);
  thread_ = std::thread([this] { run(); });
  if (s_.real_time && s_.priority > 0) {
    sched_param param{};
    param.sched_priority = s_.priority;
    pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param);  // best effort
  }
}

void SimPhantom::stop() noexcept {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
}

void SimPhantom::wait() noexcept {
  if (thread_.joinable()) thread_.join();
}

void SimPhantom::tick(std::size_t k) noexcept {
  const double dt = 1.0 / s_.rate_hz;
  const double t = static_cast<double>(k) * dt;
  const double depth = hand_->depth_mm(t);
  const double encoder = std::round(depth / s_.encoder_resolution_mm) * s_.encoder_resolution_mm;
  Vec3 position{};
  for (int i = 0; i < 3; ++i)
    position[static_cast<std::size_t>(i)] =
        s_.surface_mm[static_cast<std::size_t>(i)] + s_.axis[static_cast<std::size_t>(i)] * encoder;
  const Vec3 command = servo_->tick(position, t);
  // The command's component against the axis resists insertion.
  const double along =
      -(command[0] * s_.axis[0] + command[1] * s_.axis[1] + command[2] * s_.axis[2]);
  pending_.back() = forced_off_.load(std::memory_order_relaxed) ? 0.0 : along;
  const double applied = pending_.front();  // one tick late
  for (std::size_t i = 0; i + 1 < pending_.size(); ++i) pending_[i] = pending_[i + 1];
  const double alpha = 1.0 - std::exp(-2.0 * std::numbers::pi * s_.force_bandwidth_hz * dt);
  output_N_ += alpha * (applied - output_N_);
  if (forced_off_.load(std::memory_order_relaxed)) output_N_ = 0.0;
  if (felt_.size() < felt_.capacity()) felt_.push_back({t, depth, output_N_});
  ticks_.fetch_add(1, std::memory_order_relaxed);
}

void SimPhantom::run() noexcept {
  const auto period_ns = static_cast<std::int64_t>(1e9 / s_.rate_hz);
  timespec next{};
  clock_gettime(CLOCK_MONOTONIC, &next);
  const auto ticks = static_cast<std::size_t>(hand_->duration_s() * s_.rate_hz);
  for (std::size_t k = 0; k < ticks && !stop_.load(std::memory_order_relaxed); ++k) {
    if (s_.real_time) {
      next.tv_nsec += period_ns;
      while (next.tv_nsec >= 1'000'000'000) next.tv_nsec -= 1'000'000'000, ++next.tv_sec;
      while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr) != 0) {
      }
    }
    tick(k);
  }
  running_.store(false);
}

}  // namespace rig::drivers
