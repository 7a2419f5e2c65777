#pragma once
// Locks every page of the process in RAM, now and later (mlockall MCL_CURRENT | MCL_FUTURE), so
// that a real-time thread never waits on a page fault. Not only swap: with no swap at all a host's
// reclaim still drops clean file pages, the code of an idle binary among them (a VM's proactive
// reclaim, e.g. DAMON `pageout`, does so within seconds), and faulting them back in from a busy
// disk stalls the thread for milliseconds.
//
// Under AddressSanitizer or ThreadSanitizer the runtime intercepts mlockall() as a no-op that
// returns 0 (its shadow memory is terabytes of reservation): the lock would be reported and not
// held. There the system call is made directly, with MCL_ONFAULT (each page locked once touched;
// the shadow is never populated), and the result says so; the file-backed mappings (code and
// data of the binary and its libraries) are read in and locked at once, as in a plain build.
#include <string>

namespace rig::drivers {

struct ProcessMemoryLock {
  bool locked = false;
  bool on_fault_only =
      false;          // MCL_ONFAULT: pages lock as they are first touched (sanitizer builds)
  std::string error;  // why not, when !locked (strerror of the call)
};

// Never throws. Call before starting threads that must not fault.
ProcessMemoryLock lock_process_memory_in_ram();

}  // namespace rig::drivers
