# Inside the VM (driven by power_cut.sh): mount the archive disk (ext4 replays its journal),
# start rig-sim and rigd (which marks the run cut by the last power loss `interrupted`), print
# the archive's state, then - unless this is the final check boot (rigmode=check on the kernel
# command line) - home, tare, start a run and print the loop's cycle count until the power goes.
set -u
for m in virtio_pci virtio_blk crc32c_generic ext4; do modprobe $m || exit 1; done
ip link set lo up
mkdir -p /mnt/rig && mount -t ext4 /dev/vda /mnt/rig || exit 1
archive=/mnt/rig/archive.sqlite
export RIG_API=http://127.0.0.1:8080
# The eye close to the home switch and fast homing, as in the durability test: every boot homes.
# rig-sim on the second vCPU (--cpu 1) at SCHED_FIFO 70, below rigd's loop (80), as in the three
# passing quiet runs (until 2026-11-27 a `chrt -f 81` here was undone by rig-sim's own 70).
# rig demo and the tests now put rig-sim and the loop on one CPU with rig-sim at 81
# (daemon/cli/shared_cpu.hpp); this VM keeps the measured arrangement until that is measured
# here too (docs/faults.md, power loss item 6).
# Its heartbeat (every 5 ms: the guest's clock and the age of rigd's last DAQ read [us]) goes to
# the second serial port, which the host reads as it arrives (heartbeat_watch.py).
rig-sim --cpu 1 --rt-priority 70 --port 1502 --surface-mm 12 --heartbeat-fd 3 --heartbeat-ms 5 \
  3>/dev/ttyS1 > /tmp/rig-sim.log 2>&1 &
# TCG emulation runs both processes several times slower than the hardware: the link,
# lost-write and overrun interlocks get room (the subject here is the archive, not the link):
# rig-sim's replies miss the 950 us time-out in runs of cycles, so 3 lost writes in a row (the
# shipped safety.max_failed_writes) faulted most boots while homing; 400 stays below the VM's
# 1000 ms DAQ watchdog. The overrun storm is off (64 overruns can never fall within a 1-cycle
# window): TCG overruns whole stretches. Following error 20 mm (was 5): on a fully busy host the
# VM's vCPUs sat still for half a second and more, the carriage fell 5 mm behind its 10 mm/s
# homing reference and every boot faulted before it cut (2026-11-27).
rigd --config /etc/rig/rigd.sim.toml --set "archive.path=\"$archive\"" \
  --set 'model.file="/etc/rig/paper-interpreted.toml"' --set 'api.web_root="/tmp"' \
  --set motion.surface_mm=12 --set motion.park_mm=10 --set motion.homing_velocity_mm_s=10 \
  --set motion.retract_velocity_mm_s=10 --set safety.link_lost_after_ms=500 --set daq.watchdog_ms=1000 \
  --set safety.max_failed_writes=400 --set daq.response_timeout_us=950 --set safety.overrun_storm_missed_cycles=128 \
  --set safety.overrun_storm_window_cycles=1 --set safety.max_following_error_mm=20 --set safety.tare_cycles=20 \
  --set iop.settle_time_s=0.3 --set stream.udp_enabled=true --set stream.udp_port=9870 > /tmp/rigd.log 2>&1 &
rigd=$!
for i in $(seq 150); do rig status > /dev/null 2>&1 && break; kill -0 $rigd || break; sleep 0.2; done
rig status > /dev/null || { cat /tmp/rigd.log /tmp/rig-sim.log; exit 1; }
# The loop's start on CLOCK_MONOTONIC [s] (a sample's time there = this + its t_s), from one
# datagram of rigd's UDP stream: the host puts the archived samples on the heartbeat's clock.
loop_start=$(timeout 10 socat -u UDP-RECVFROM:9870,bind=127.0.0.1 STDOUT 2>/dev/null |
  sed -n 's/.*"loop_start_monotonic_s":\([0-9.e+-]*\).*/\1/p')
echo "LOOPSTART ${loop_start:--1}"
echo "INTEGRITY $(sqlite3 "$archive" 'PRAGMA integrity_check' 2>&1 | tr '\n' ' ')"
sqlite3 -separator ' ' "$archive" "SELECT 'RUNROW', r.id, r.outcome, COUNT(s.idx), IFNULL(MIN(s.idx), -1), IFNULL(MAX(s.idx), -1),
  IFNULL(MAX(s.t_s), -1) FROM runs r LEFT JOIN samples s ON s.run_id = r.id GROUP BY r.id ORDER BY r.id" || exit 1
grep -q rigmode=check /proc/cmdline && exit 0
# The DAQ link comes up a moment after the API (the first replies under TCG are slow).
for i in $(seq 20); do out=$(rig home 2>&1) && break; echo "HOME try $i: $out" | head -2; rig reset > /dev/null 2>&1; sleep 0.2; done
echo "HOMED"
for i in $(seq 20); do rig tare > /dev/null 2>&1 && break; sleep 0.3; done
rig status | grep -q 'yes / yes' || { rig status; cat /tmp/rigd.log; exit 1; }
# Commands are refused in a cycle whose DAQ reply was late (TCG): ask again.
for i in $(seq 20); do
  run=$(rig run --iop 15 --velocity 4 --depth 8 --eye P --no-wait 2>/dev/null | sed -n 's/^run \([0-9]*\) armed.*/\1/p')
  [ -n "$run" ] && break; sleep 0.2
done
[ -n "$run" ] || { cat /tmp/rigd.log; exit 1; }
# The host cuts the power at a random moment after the first of these lines: the loop's cycle
# and state, then the run's last sample committed to the archive as a reader sees it (WAL: only
# committed transactions), which must survive the cut. The poller is the test's instrument, not
# part of the rig: at nice 19 (wget and sqlite3 inherit it) it yields the vCPU to rigd's
# recorder. Until 2026-12-02 it ran at rigd's priority without a pause, and rigd's commits
# started 20 ms late at the median of boots (worst 130 ms; docs/faults.md power loss item 12).
renice -n 19 -p $$ > /dev/null || exit 1
while :; do
  status=$(wget -qO- "$RIG_API/api/status")
  committed=$(sqlite3 "$archive" "SELECT IFNULL(MAX(idx), -1) FROM samples WHERE run_id = $run" 2>/dev/null || echo -1)
  echo "CYC $run $(echo "$status" | sed -n 's/.*"cycles":\([0-9]*\).*/\1/p') $(echo "$status" | sed -n 's/.*"state":"\([A-Za-z]*\)".*/\1/p') ${committed:--1}"
  # rigd's own tally of its commits (status archive_commits, keys in alphabetical order): the
  # longest commit, the latest start and the longest and last exposure [ms] - a slow disk or a
  # starved recorder, when a cut loses more than one flush interval.
  echo "$status" | sed -n 's/.*"last_exposure_ms":\([0-9.e+-]*\).*"max_commit_ms":\([0-9.e+-]*\).*"max_exposure_ms":\([0-9.e+-]*\).*"max_late_ms":\([0-9.e+-]*\).*/COMMITS \2 \4 \3 \1/p'
done
