#pragma once
// A GPIO chip in memory: another thread flips inputs (a technician's hand on the e-stop,
// a limit switch) and watches outputs; the RT loop polls it like the kernel's chip.
// Lock-free: per line an atomic level, an edge counter and the edge's time. Levels in
// between two polls can be lost (like a very short pulse under a slow poll), edges cannot.
#include <array>
#include <atomic>
#include <cstdint>

#include "gpio/gpio_line_bank.hpp"

namespace rig::drivers {

class SimGpioLineBank final : public GpioLineBank {
 public:
  static constexpr std::size_t kLines = 8;

  // Simulation side (any thread). timestamp_ns on CLOCK_MONOTONIC.
  void set_input(std::size_t input, bool active, std::int64_t timestamp_ns) noexcept;
  bool output(std::size_t output) const noexcept;
  // When the output last changed [ns], as measured by the bank's own monotonic clock.
  std::int64_t output_changed_ns(std::size_t output) const noexcept;

  IoStatus read_levels(std::span<bool> levels) noexcept override;
  IoStatus poll_edges(std::span<LineEdge> edges, std::size_t& count) noexcept override;
  IoStatus set_output(std::size_t output, bool active) noexcept override;

 private:
  struct Input {
    std::atomic<bool> level{false};
    std::atomic<std::int64_t> edge_ns{0};
    std::atomic<std::uint64_t> edges{0};
    std::uint64_t edges_seen = 0;  // poller's side only
  };
  struct Output {
    std::atomic<bool> level{false};
    std::atomic<std::int64_t> changed_ns{0};
  };
  std::array<Input, kLines> inputs_{};
  std::array<Output, kLines> outputs_{};
};

}  // namespace rig::drivers
