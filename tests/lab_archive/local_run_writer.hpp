#pragma once
// Writes runs into a local SQLite archive the way rigd's recorder does (batches committed
// one at a time), for the lab archive's tests and benchmark; and a checksum of a run's data
// that any difference in any value or in the order of samples changes.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "archive.hpp"

namespace rig::testing {

class LocalRunWriter {
 public:
  explicit LocalRunWriter(archive::Archive& archive) : archive_(archive) {}

  std::int64_t start(const std::string& eye_id, const std::string& eye_lot,
                     const std::string& operator_name = "ann") {
    archive::NewRun run;
    run.eye_id = eye_id;
    run.operator_name = operator_name;
    run.surface_mm = 20.0;
    run.post_mortem_h = 3.25;
    run.notes = "tab\tand newline\nand backslash \\ in notes";
    run.meta = {{"eye_lot", eye_lot}, {"blade_lot", "B-12"}, {"temperature_C", "21.5"}};
    const std::int64_t id = archive_.create_run(run);
    archive_.mark_started(id);
    cycle_ = 1000;
    return id;
  }
  // Appends `count` samples in one committed batch; values vary so a shifted sample shows.
  void append(std::int64_t run_id, std::int64_t count) {
    archive_.begin();
    for (std::int64_t i = 0; i < count; ++i, ++cycle_) {
      rt::Sample s;
      s.run_id = run_id;
      s.cycle = cycle_;
      const double k = static_cast<double>(cycle_);
      s.t_s = 5.0 + k * 1e-3;
      s.position_mm = 19.0 + k * 2e-6;
      s.force_N = 0.25 * std::sin(k * 0.013) + 1e-17 * k;
      s.iop_mmHg = 15.0 + 0.1 * std::cos(k * 0.007);
      s.velocity_mm_s = 2.0 + 1e-3 * std::sin(k);
      s.motor_volts = 3.3 + 1e-4 * k;
      s.pump_command = 0.4;
      s.state = rt::RunState::kCutting;
      s.io_ok = cycle_ % 997 == 0 ? 0 : 1;
      archive_.append_sample(s);
    }
    archive_.add_event(run_id, 5.0 + static_cast<double>(cycle_) * 1e-3, "batch",
                       "after cycle " + std::to_string(cycle_));
    archive_.commit();
  }
  void finish(std::int64_t run_id) { archive_.finish_run(run_id, "completed", ""); }

 private:
  archive::Archive& archive_;
  std::uint64_t cycle_ = 1000;
};

// FNV-1a over the bit patterns of every value of a run (t, x, F, every channel in order).
inline std::uint64_t run_checksum(const model::RunData& run) {
  std::uint64_t hash = 14695981039346656037ULL;
  auto mix = [&hash](const std::vector<double>& values) {
    for (const double v : values) {
      std::uint64_t bits = 0;
      std::memcpy(&bits, &v, sizeof bits);
      for (int b = 0; b < 8; ++b) {
        hash ^= (bits >> (8 * b)) & 0xFF;
        hash *= 1099511628211ULL;
      }
    }
  };
  mix(run.t_s);
  mix(run.x_mm);
  mix(run.force_N);
  for (const auto& channel : run.channels) mix(channel.values);
  return hash;
}

}  // namespace rig::testing
