// The memory lock of rigd and rig-sim holds pages in RAM in every build. A sanitizer runtime
// answers mlockall() with 0 and locks nothing: this test caught that (VmLck 0 kB in the ASan
// tree while rigd logged "memory locked"), and runs in the ASan and TSan trees for that reason.
#include <gtest/gtest.h>
#include <sys/mman.h>

#include <cctype>
#include <cstddef>
#include <fstream>
#include <memory>
#include <string>
#include <utility>

#include "clock/process_memory_lock.hpp"

namespace {

// VmLck of this process [kB], from /proc/self/status.
long locked_kB() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmLck:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

TEST(ProcessMemoryLock, HoldsTheProcessesPagesInRamAndThoseItTouchesLater) {
  ASSERT_EQ(locked_kB(), 0) << "nothing is locked before the call";
  const rig::drivers::ProcessMemoryLock lock = rig::drivers::lock_process_memory_in_ram();
  ASSERT_TRUE(lock.locked) << "mlockall refused: " << lock.error << " (the tests run as root)";
  const long after_lock_kB = locked_kB();
  EXPECT_GT(after_lock_kB, 0) << "reported locked, and nothing is";
  // MCL_FUTURE: memory mapped later is locked too (under a sanitizer, once touched).
  constexpr std::size_t kBytes = std::size_t{16} << 20;
  auto later = std::make_unique<unsigned char[]>(kBytes);
  for (std::size_t i = 0; i < kBytes; i += 4096) later[i] = static_cast<unsigned char>(i);
  EXPECT_GE(locked_kB() - after_lock_kB, 15L * 1024) << "16 MiB touched after the lock";
  munlockall();
}

// Size and Rss [kB] summed over the executable mappings of files (this binary and its
// libraries: libstdc++'s code, most of which the test never runs), from /proc/self/smaps;
// each must be locked (VmFlags "lo"). Rss counts the pages mapped in: code never run is not.
std::pair<long, long> code_size_and_resident_kB() {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool in_code = false;
  long size_kB = 0, resident = 0;
  while (std::getline(smaps, line)) {
    const bool header = !line.empty() && std::isxdigit(static_cast<unsigned char>(line[0])) &&
                        line.find(':') > line.find(' ');
    if (header) {
      in_code = line.find(" r-xp ") != std::string::npos && line.find(" /") != std::string::npos;
    } else if (in_code && line.rfind("Size:", 0) == 0) {
      size_kB += std::stol(line.substr(5));
    } else if (in_code && line.rfind("Rss:", 0) == 0) {
      resident += std::stol(line.substr(4));
    } else if (in_code && line.rfind("VmFlags:", 0) == 0 && line.find(" lo") == std::string::npos) {
      resident = -1000000000;  // a mapping of code that is not locked: fails the test below
    }
  }
  return {size_kB, resident};
}

TEST(ProcessMemoryLock, ReadsInAndLocksTheCodeOfTheBinaryAtOnceNotWhenItFirstRuns) {
  const rig::drivers::ProcessMemoryLock lock = rig::drivers::lock_process_memory_in_ram();
  ASSERT_TRUE(lock.locked) << lock.error;
  const auto [size_kB, resident_kB] = code_size_and_resident_kB();
  ASSERT_GT(size_kB, 0) << "no executable mapping of the test binary found in /proc/self/smaps";
  // Code this test never ran is locked too: read in now, not from the disk when a fault path first
  // runs.
  EXPECT_GE(resident_kB, size_kB * 9 / 10)
      << resident_kB << " of " << size_kB << " kB of locked code in RAM";
  munlockall();
}

TEST(ProcessMemoryLock, SaysWhenPagesLockOnlyAsTheyAreTouched) {
  const rig::drivers::ProcessMemoryLock lock = rig::drivers::lock_process_memory_in_ram();
  ASSERT_TRUE(lock.locked) << lock.error;
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  EXPECT_TRUE(lock.on_fault_only) << "a sanitizer's terabytes of shadow must not be populated";
#else
  EXPECT_FALSE(lock.on_fault_only);
#endif
  EXPECT_TRUE(lock.error.empty());
  munlockall();
}

}  // namespace
