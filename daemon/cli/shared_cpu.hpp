#pragma once
// The simulated rig's CPU: rig-sim (`--cpu`) and rigd's loop (`loop.cpu`) are pinned to one
// CPU, so that a CPU the machine holds still (a VM's vCPU throttled by its host: mostly 10-12 ms,
// docs/loop-timing.md) stops the simulated DAQ and the loop together. A real DAQ has its own
// CPU and never stalls; a simulated one that stalls apart from rigd is silent while rigd runs
// (a "lost link") or lets rigd's stall run on its own clock (a "tripped watchdog"). On one CPU,
// rigd wakes late after such a stall (excused) and rig-sim discounts its own (its clock stops).

namespace rig::cli {

// One of the CPUs this process may run on, spread by process id and, within one process, by
// call (two rigs side by side may share one; that is fine: both pairs stop together).
// -1 when there is only one CPU.
int pick_shared_cpu();

}  // namespace rig::cli
