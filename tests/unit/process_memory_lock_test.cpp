// The memory lock of rigd and rig-sim holds pages in RAM in every build. A sanitizer runtime
// answers mlockall() with 0 and locks nothing: this test caught that (VmLck 0 kB in the ASan
// tree while rigd logged "memory locked"), and runs in the ASan and TSan trees for that reason.
// It reads each mapping's Locked figure in /proc/self/smaps, not the process's VmLck (below).
#include <gtest/gtest.h>
#include <sys/mman.h>

#include <cctype>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <utility>

#include "clock/process_memory_lock.hpp"

namespace {

// A mapping's first line in /proc/self/smaps ("7f..-7f.. r-xp ... /path"), not a "Key: value" line.
bool is_mapping_header(const std::string& line) {
  return !line.empty() && std::isxdigit(static_cast<unsigned char>(line[0])) &&
         line.find(':') > line.find(' ');
}

// Locked [kB] of the mapping that holds `address`, from /proc/self/smaps; -1 if none does.
// Per mapping, not the process's VmLck: on some kernels (6.18 here, 2026-12-04) VmLck wraps
// below zero under TSan (18446744069951540368 kB), whose shadow mappings span terabytes.
long locked_kB_of_mapping_at(const void* address) {
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    const std::size_t dash = line.find('-');
    if (is_mapping_header(line) && dash != std::string::npos) {
      const std::uintptr_t from = std::stoull(line.substr(0, dash), nullptr, 16);
      const std::uintptr_t to = std::stoull(line.substr(dash + 1), nullptr, 16);
      inside = at >= from && at < to;
    } else if (inside && line.rfind("Locked:", 0) == 0) {
      return std::stol(line.substr(7));
    }
  }
  return -1;
}

// `bytes` of heap, every page written [B].
std::unique_ptr<unsigned char[]> touched(std::size_t bytes) {
  auto memory = std::make_unique<unsigned char[]>(bytes);
  for (std::size_t i = 0; i < bytes; i += 4096) memory[i] = static_cast<unsigned char>(i);
  return memory;
}

TEST(ProcessMemoryLock, HoldsTheProcessesPagesInRamAndThoseItTouchesLater) {
  constexpr std::size_t kBytes = std::size_t{16} << 20;
  const auto before = touched(kBytes);
  ASSERT_EQ(locked_kB_of_mapping_at(before.get()), 0) << "nothing is locked before the call";
  const rig::drivers::ProcessMemoryLock lock = rig::drivers::lock_process_memory_in_ram();
  ASSERT_TRUE(lock.locked) << "mlockall refused: " << lock.error << " (the tests run as root)";
  EXPECT_GE(locked_kB_of_mapping_at(before.get()), 15L * 1024)
      << "reported locked, and 16 MiB in RAM before the call are not";
  // MCL_FUTURE: memory mapped later is locked too (under a sanitizer, once touched).
  const auto later = touched(kBytes);
  EXPECT_GE(locked_kB_of_mapping_at(later.get()), 15L * 1024) << "16 MiB touched after the lock";
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
    if (is_mapping_header(line)) {
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
