#pragma once
// Who is importing a run: "BOOT_ID PID START_TICKS" of a `rig import` process, kept with a
// run while it is 'importing'. A run whose importer is gone (killed, crashed, the machine
// rebooted) will never be finished by it; a pid alone could have been reused, so the boot
// and the process's start time (in clock ticks since boot) must match too.
#include <string>

namespace rig::archive {

// This process's identity, as above.
std::string current_import_process();

// True while the process named by identity runs (same boot, same pid, same start time).
// An identity that does not parse is taken as gone.
bool import_process_alive(const std::string& identity);

}  // namespace rig::archive
