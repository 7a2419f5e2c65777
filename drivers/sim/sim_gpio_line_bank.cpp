#include "sim_gpio_line_bank.hpp"

#include <ctime>

namespace rig::drivers {
namespace {
std::int64_t monotonic_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
}  // namespace

void SimGpioLineBank::set_input(std::size_t input, bool active,
                                std::int64_t timestamp_ns) noexcept {
  if (input >= kLines) return;
  Input& line = inputs_[input];
  line.level.store(active, std::memory_order_relaxed);
  line.edge_ns.store(timestamp_ns, std::memory_order_relaxed);
  line.edges.fetch_add(1, std::memory_order_release);
}

bool SimGpioLineBank::output(std::size_t output) const noexcept {
  return output < kLines && outputs_[output].level.load(std::memory_order_acquire);
}

std::int64_t SimGpioLineBank::output_changed_ns(std::size_t output) const noexcept {
  return output < kLines ? outputs_[output].changed_ns.load(std::memory_order_acquire) : 0;
}

IoStatus SimGpioLineBank::read_levels(std::span<bool> levels) noexcept {
  for (std::size_t i = 0; i < levels.size() && i < kLines; ++i)
    levels[i] = inputs_[i].level.load(std::memory_order_acquire);
  return IoStatus::kOk;
}

IoStatus SimGpioLineBank::poll_edges(std::span<LineEdge> edges, std::size_t& count) noexcept {
  count = 0;
  for (std::size_t i = 0; i < kLines && count < edges.size(); ++i) {
    Input& line = inputs_[i];
    const std::uint64_t total = line.edges.load(std::memory_order_acquire);
    if (total == line.edges_seen) continue;
    line.edges_seen = total;
    edges[count++] = LineEdge{i, line.level.load(std::memory_order_relaxed),
                              line.edge_ns.load(std::memory_order_relaxed)};
  }
  return IoStatus::kOk;
}

IoStatus SimGpioLineBank::set_output(std::size_t output, bool active) noexcept {
  if (output >= kLines) return IoStatus::kNotReady;
  outputs_[output].changed_ns.store(monotonic_ns(), std::memory_order_relaxed);
  outputs_[output].level.store(active, std::memory_order_release);
  return IoStatus::kOk;
}

}  // namespace rig::drivers
