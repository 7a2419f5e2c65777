#include "shared_cpu.hpp"

#include <sched.h>
#include <unistd.h>

#include <atomic>
#include <vector>

namespace rig::cli {

int pick_shared_cpu() {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) return -1;
  std::vector<int> cpus;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (CPU_ISSET(cpu, &allowed)) cpus.push_back(cpu);
  }
  if (cpus.size() < 2) return -1;  // nothing to choose: everything runs on that one CPU
  static std::atomic<unsigned> rigs_started{0};  // several rigs of one process take turns
  return cpus[(static_cast<std::size_t>(getpid()) + rigs_started.fetch_add(1)) % cpus.size()];
}

}  // namespace rig::cli
