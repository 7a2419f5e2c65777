#include "process_memory_lock.hpp"

#include <sys/mman.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RIG_SANITIZER_INTERCEPTS_MLOCKALL 1
#else
#define RIG_SANITIZER_INTERCEPTS_MLOCKALL 0
#endif

#ifndef MCL_ONFAULT
#define MCL_ONFAULT 4  // Linux >= 4.4; older libc headers lack the name
#endif

namespace rig::drivers {

#if RIG_SANITIZER_INTERCEPTS_MLOCKALL
namespace {
// The code and data of the binary and its libraries (the file-backed mappings), read in and
// locked now, as MCL_CURRENT does in a plain build. With MCL_ONFAULT alone, code first run
// later (a fault path) is read from the disk at that moment, on a host that reclaims idle page
// cache and may be writing out a build (our guess for a 1.2 s stall of the loop in the ASan
// tier, 2026-12-04). Anonymous mappings, the runtime's shadow among them, stay on-fault. Setup
// only.
void lock_file_mappings_now() {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    unsigned long start = 0, end = 0, offset = 0, inode = 0;
    char perms[5] = {};
    char device[16] = {};
    if (std::sscanf(line.c_str(), "%lx-%lx %4s %lx %15s %lu", &start, &end, perms, &offset, device,
                    &inode) != 6)
      continue;
    if (inode == 0 || perms[0] != 'r' || line.find(" /dev/") != std::string::npos) continue;
    ::syscall(SYS_mlock, start, end - start);  // best effort; the runtime's mlock() is a no-op too
  }
}
}  // namespace
#endif

ProcessMemoryLock lock_process_memory_in_ram() {
  ProcessMemoryLock result;
#if RIG_SANITIZER_INTERCEPTS_MLOCKALL
  // The interceptor would return 0 and lock nothing: go past it, to the kernel.
  const long rc = ::syscall(SYS_mlockall, MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT);
  result.on_fault_only = true;
  if (rc == 0) lock_file_mappings_now();
#else
  const long rc = ::mlockall(MCL_CURRENT | MCL_FUTURE);
#endif
  result.locked = rc == 0;
  if (!result.locked) result.error = std::strerror(errno);
  return result;
}

}  // namespace rig::drivers
