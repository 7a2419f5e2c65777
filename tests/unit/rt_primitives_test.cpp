// Lock-free channels out of the RT loop, and the jitter histogram.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "jitter_histogram.hpp"
#include "latest_value.hpp"
#include "spsc_ring.hpp"

namespace rig::rt {
namespace {

TEST(SpscRing, RejectsACapacityThatIsNotAPowerOfTwo) {
  EXPECT_THROW(SpscRing<int>(100), std::invalid_argument);
}

TEST(SpscRing, ReportsFullInsteadOfOverwriting) {
  SpscRing<int> ring(4);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.try_push(i));
  EXPECT_FALSE(ring.try_push(99));
  int value = -1;
  EXPECT_TRUE(ring.try_pop(value));
  EXPECT_EQ(value, 0);
  EXPECT_TRUE(ring.try_push(4));
}

TEST(SpscRing, DeliversEveryItemInOrderAcrossThreads) {
  SpscRing<std::uint64_t> ring(1024);
  constexpr std::uint64_t kItems = 200000;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kItems;) {
      if (ring.try_push(i)) ++i;
    }
  });
  std::uint64_t expected = 0;
  while (expected < kItems) {
    std::uint64_t value = 0;
    if (ring.try_pop(value)) {
      ASSERT_EQ(value, expected);
      ++expected;
    }
  }
  producer.join();
}

struct Wide {
  std::uint64_t a = 0, b = 0, c = 0, d = 0;
};

TEST(LatestValue, ReadersNeverSeeATornValue) {
  LatestValue<Wide> latest;
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    for (std::uint64_t i = 1; !stop.load(); ++i) latest.publish({i, i, i, i});
  });
  std::uint64_t last = 0;
  for (int i = 0; i < 100000; ++i) {
    const Wide w = latest.read();
    ASSERT_TRUE(w.a == w.b && w.b == w.c && w.c == w.d);
    ASSERT_GE(w.a, last);  // never goes back in time
    last = w.a;
  }
  stop.store(true);
  writer.join();
}

TEST(JitterHistogram, PercentilesLandInTheRightBins) {
  JitterHistogram h;
  for (int i = 0; i < 990; ++i) h.record(10'000);  // 10 us
  for (int i = 0; i < 10; ++i) h.record(900'000);  // 900 us
  const auto s = h.snapshot();
  EXPECT_EQ(s.total, 1000U);
  EXPECT_DOUBLE_EQ(s.percentile_us(0.5), 11.0);  // upper edge of the 10 us bin
  EXPECT_GE(s.percentile_us(0.999), 900.0);
  EXPECT_LE(s.percentile_us(0.999), 900.0 * 1.13);  // 8 bins per octave: within 12.5 %
  EXPECT_EQ(s.max_ns, 900'000);
}

TEST(JitterHistogram, BinsAreMonotonicAcrossTheLinearToLogBoundary) {
  double previous = 0.0;
  for (std::int64_t us = 0; us < 2'000'000; us = us < 200 ? us + 1 : us * 11 / 10) {
    const double edge = JitterHistogram::upper_edge_us(JitterHistogram::bin_of(us));
    EXPECT_GE(edge, previous);
    EXPECT_GT(edge, static_cast<double>(us));
    previous = edge;
  }
}

}  // namespace
}  // namespace rig::rt
