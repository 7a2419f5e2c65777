#pragma once
// Debounce for the rig's safety inputs (limit switches, e-stop, drive fault), fed with the
// kernel's edge events. Asymmetric on purpose: a line becoming active is believed at once
// (stopping early is the safe error), a line becoming inactive only after it has stayed
// inactive for the debounce time. An activation is also latched until the next read, so
// a press shorter than one loop period is never missed. Fixed capacity, no allocation.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace rig::drivers {

class InputDebouncer {
 public:
  static constexpr std::size_t kMaxInputs = 16;

  explicit InputDebouncer(std::int64_t debounce_ns) noexcept : debounce_ns_(debounce_ns) {}

  // Known levels at start-up (no bounce assumed) [ns on CLOCK_MONOTONIC].
  void reset(std::span<const bool> levels, std::int64_t now_ns) noexcept;
  void on_edge(std::size_t input, bool active, std::int64_t timestamp_ns) noexcept;
  // Debounced level at now_ns; clears the latch of that input.
  bool read(std::size_t input, std::int64_t now_ns) noexcept;

 private:
  struct Line {
    bool raw = false;               // last level the kernel reported
    std::int64_t raw_since_ns = 0;  // when it took that level
    bool stable = false;            // debounced level
    bool latched = false;           // became active since the last read
  };
  std::int64_t debounce_ns_;
  std::array<Line, kMaxInputs> lines_{};
};

}  // namespace rig::drivers
