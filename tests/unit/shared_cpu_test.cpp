// The CPU rig demo and the test harness pin rig-sim and rigd's loop to (daemon/cli/shared_cpu.hpp).
#include <gtest/gtest.h>
#include <sched.h>

#include <thread>

#include "shared_cpu.hpp"

namespace rig::cli {
namespace {

bool allowed(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  sched_getaffinity(0, sizeof set, &set);
  return cpu >= 0 && CPU_ISSET(cpu, &set);
}

TEST(SharedCpu, TwoRigsOfOneProcessGetTwoDifferentCpusBothAllowedToIt) {
  cpu_set_t set;
  CPU_ZERO(&set);
  ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
  if (CPU_COUNT(&set) < 2) {
    EXPECT_EQ(pick_shared_cpu(), -1) << "one CPU: nothing to pin";
    return;
  }
  const int first = pick_shared_cpu();
  const int second = pick_shared_cpu();
  EXPECT_TRUE(allowed(first)) << first;
  EXPECT_TRUE(allowed(second)) << second;
  EXPECT_NE(first, second);
}

TEST(SharedCpu, AProcessHeldToOneCpuPinsNothing) {
  cpu_set_t set;
  CPU_ZERO(&set);
  ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
  int first_allowed = 0;
  while (!CPU_ISSET(first_allowed, &set)) ++first_allowed;
  int picked = 0;
  std::thread held([&] {  // affinity is per thread: only this one is held to one CPU
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(first_allowed, &one);
    ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
    picked = pick_shared_cpu();
  });
  held.join();
  EXPECT_EQ(picked, -1);
}

}  // namespace
}  // namespace rig::cli
