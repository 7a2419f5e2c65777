#pragma once
// The few things rigd needs from a GPIO chip, so that the libgpiod API version lives in
// one file: libgpiod 1.6 (v1 API, Debian 12) today, a v2 bank later with the same shape.
// Inputs are requested with both-edge events; outputs start inactive.
#include <cstddef>
#include <cstdint>
#include <span>

#include "rig/drivers/io_status.hpp"

namespace rig::drivers {

struct LineEdge {
  std::size_t input = 0;          // index into the bank's input list
  bool active = false;            // logical level after the edge (active-low already applied)
  std::int64_t timestamp_ns = 0;  // kernel's CLOCK_MONOTONIC time of the edge [ns]
};

class GpioLineBank {
 public:
  virtual ~GpioLineBank() = default;
  // Current logical levels of all inputs (setup and resynchronisation only).
  virtual IoStatus read_levels(std::span<bool> levels) noexcept = 0;
  // Edges queued by the kernel since the last call; never waits. count = edges written.
  virtual IoStatus poll_edges(std::span<LineEdge> edges, std::size_t& count) noexcept = 0;
  virtual IoStatus set_output(std::size_t output, bool active) noexcept = 0;
};

}  // namespace rig::drivers
