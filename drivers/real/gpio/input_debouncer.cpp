#include "input_debouncer.hpp"

namespace rig::drivers {

void InputDebouncer::reset(std::span<const bool> levels, std::int64_t now_ns) noexcept {
  for (std::size_t i = 0; i < levels.size() && i < kMaxInputs; ++i)
    lines_[i] = Line{levels[i], now_ns, levels[i], false};
}

void InputDebouncer::on_edge(std::size_t input, bool active, std::int64_t timestamp_ns) noexcept {
  if (input >= kMaxInputs) return;
  Line& line = lines_[input];
  // An edge to the level the line already had: the kernel labels an edge by reading the line
  // when it handles the interrupt, so a pulse shorter than that latency (a slap on the
  // e-stop, seen under a loaded or emulated kernel) arrives as two edges to "inactive". A
  // line does not change without going somewhere: treat it as a press, never lose it.
  // The same edge during a release is a bounce: the line was active again in between, so the
  // wait for it to stay inactive restarts there, as for a correctly labelled bounce.
  if (!active && !line.raw) line.latched = true;
  if (line.raw != active || !active) line.raw_since_ns = timestamp_ns;
  line.raw = active;
  if (active) {
    line.stable = true;
    line.latched = true;
  }
}

bool InputDebouncer::read(std::size_t input, std::int64_t now_ns) noexcept {
  if (input >= kMaxInputs) return false;
  Line& line = lines_[input];
  if (line.raw != line.stable && now_ns - line.raw_since_ns >= debounce_ns_) line.stable = line.raw;
  const bool level = line.stable || line.latched;
  line.latched = false;
  return level;
}

}  // namespace rig::drivers
