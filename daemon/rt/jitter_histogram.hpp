#pragma once
// Histogram of loop wake-up latency (actual wake time - deadline). Log-linear bins:
// 1 us wide below 64 us, then 8 bins per octave up to ~1 s. The RT thread only does
// relaxed increments; readers take a snapshot and compute percentiles.
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace rig::rt {

class JitterHistogram {
 public:
  static constexpr int kLinearBins = 64;
  static constexpr int kSubBins = 8;
  static constexpr int kOctaves = 14;
  static constexpr int kBinCount = kLinearBins + kSubBins * kOctaves + 1;  // + overflow

  void record(std::int64_t latency_ns) noexcept;
  void reset() noexcept;

  struct Snapshot {
    std::array<std::uint64_t, kBinCount> counts{};
    std::uint64_t total = 0;
    std::int64_t max_ns = 0;
    double percentile_us(double fraction) const;  // upper edge of the bin holding it
  };
  Snapshot snapshot() const;

  static int bin_of(std::int64_t latency_us) noexcept;
  static double upper_edge_us(int bin) noexcept;

 private:
  std::array<std::atomic<std::uint64_t>, kBinCount> counts_{};
  std::atomic<std::int64_t> max_ns_{0};
};

}  // namespace rig::rt
