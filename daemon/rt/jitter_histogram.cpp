#include "jitter_histogram.hpp"

#include <bit>
#include <cmath>

namespace rig::rt {

int JitterHistogram::bin_of(std::int64_t latency_us) noexcept {
  if (latency_us < 0) latency_us = 0;
  if (latency_us < kLinearBins) return static_cast<int>(latency_us);
  const auto value = static_cast<std::uint64_t>(latency_us);
  const int octave = std::bit_width(value) - 7;  // 64..127 us is octave 0
  if (octave >= kOctaves) return kBinCount - 1;
  const int sub = static_cast<int>((value >> (octave + 3)) & (kSubBins - 1));
  return kLinearBins + octave * kSubBins + sub;
}

double JitterHistogram::upper_edge_us(int bin) noexcept {
  if (bin < kLinearBins) return bin + 1.0;
  if (bin >= kBinCount - 1) return INFINITY;
  const int octave = (bin - kLinearBins) / kSubBins;
  const int sub = (bin - kLinearBins) % kSubBins;
  const double base = 64.0 * std::ldexp(1.0, octave);
  return base + base / kSubBins * (sub + 1);
}

void JitterHistogram::record(std::int64_t latency_ns) noexcept {
  counts_[static_cast<std::size_t>(bin_of(latency_ns / 1000))].fetch_add(1,
                                                                         std::memory_order_relaxed);
  if (latency_ns > max_ns_.load(std::memory_order_relaxed)) {
    max_ns_.store(latency_ns, std::memory_order_relaxed);  // single writer
  }
}

void JitterHistogram::reset() noexcept {
  for (auto& count : counts_) count.store(0, std::memory_order_relaxed);
  max_ns_.store(0, std::memory_order_relaxed);
}

JitterHistogram::Snapshot JitterHistogram::snapshot() const {
  Snapshot snap;
  for (int i = 0; i < kBinCount; ++i) {
    snap.counts[static_cast<std::size_t>(i)] =
        counts_[static_cast<std::size_t>(i)].load(std::memory_order_relaxed);
    snap.total += snap.counts[static_cast<std::size_t>(i)];
  }
  snap.max_ns = max_ns_.load(std::memory_order_relaxed);
  return snap;
}

double JitterHistogram::Snapshot::percentile_us(double fraction) const {
  if (total == 0) return 0.0;
  const double wanted = fraction * static_cast<double>(total);
  double seen = 0.0;
  for (int i = 0; i < kBinCount; ++i) {
    seen += static_cast<double>(counts[static_cast<std::size_t>(i)]);
    if (seen >= wanted) return i == kBinCount - 1 ? max_ns / 1000.0 : upper_edge_us(i);
  }
  return max_ns / 1000.0;
}

}  // namespace rig::rt
