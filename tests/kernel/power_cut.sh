#!/bin/bash
# Power loss: rigd records runs against rig-sim inside the VM, its SQLite archive on a virtio
# disk (ext4); the host cuts the VM's power (kill -9 QEMU) at a seeded random moment of each
# run (0-1.5 s into cutting; every fifth while armed), boots again and checks the archive:
# integrity_check ok, every earlier run unchanged, the cut run `interrupted` with contiguous
# samples and at most one flush interval of samples lost (archive.flush_interval_ms of
# RIGD_CONFIG): the time from the last archived sample to the guest's clock at the cut, known
# from rig-sim's heartbeat on the VM's second serial port (heartbeat_watch.py), must stay below
# the interval plus one loop period. Fails too unless every cut was checked and at least half
# hit a run while it cut. Prints a "POWER LOSS |" figure line.
# usage: power_cut.sh CACHE_DIR CUTS SEED RIGD_CONFIG MODEL_FILE PROGRAM...
set -euo pipefail
cache="$1"; cuts="$2"; seed="$3"; config="$4"; model="$5"; shift 5
limit_ms="$(sed -n 's/^flush_interval_ms *= *\([0-9]*\).*/\1/p' "$config")"
[ -n "$limit_ms" ] || { echo "FAIL: $config has no archive.flush_interval_ms"; exit 1; }
here="$(cd "$(dirname "$0")" && pwd)"
command -v qemu-system-x86_64 >/dev/null || { echo "SKIP: qemu-system-x86_64 is not installed"; exit 77; }
[ -f "$cache/ready" ] || { echo "FAIL: $cache is not prepared (prepare_kernel.sh)"; exit 1; }
work="$(mktemp -d "${TMPDIR:-/tmp}/rig-power.XXXXXX")"
qemu=""; watcher=""; disk_dir=""; cpu_group=""
cleanup() {
  kill -9 $qemu $watcher 2>/dev/null || true; wait $qemu $watcher 2>/dev/null || true
  rm -rf "$work" "$disk_dir"
  [ -z "$cpu_group" ] || { echo $$ > "$(dirname "$cpu_group")/cgroup.procs"; rmdir "$cpu_group"; } 2>/dev/null || true
}
trap cleanup EXIT
"$here/build_initramfs.sh" "$cache" "$work" "$here/scenario_power.sh" "virtio_pci virtio_blk ext4 crc32c_generic" "$@" "$(command -v sqlite3)" "$(command -v chrt)" "$(command -v socat)"
# rigd's config and model ride in a second cpio appended to the first (the kernel unpacks both).
mkdir -p "$work/extra/etc/rig" && cp "$config" "$model" "$work/extra/etc/rig/"
(cd "$work/extra" && find . | cpio -o -H newc --quiet | gzip -1 >> "$work/initrd.gz")
# 256 MiB: with the log copied only between runs (docs/faults.md power loss item 8), 64 MiB
# filled up by the ninth boot of a loaded run ("database or disk is full", 2026-12-02).
# The VM stands for the rig's own computer, which has a disk of its own: the image lives in host
# RAM (/dev/shm) where there is room, so a busy host's writers (busy-machine's dsync writes) do
# not queue the guest's flushes behind theirs. A write QEMU completed is in the image either way
# and survives its kill -9; what the guest had not yet written is lost, as at a power cut.
if [ -d /dev/shm ] && [ -w /dev/shm ] && [ "$(df -Pm /dev/shm | awk 'NR == 2 { print $4 }')" -gt 1024 ]; then
  disk_dir="$(mktemp -d /dev/shm/rig-power-disk.XXXXXX)"; else disk_dir="$work"; fi
disk="$disk_dir/archive.img"
truncate -s 256M "$disk" && mkfs.ext4 -q -F "$disk"

boot() {  # boot MODE -> $work/console.log; returns once the VM is cut (MODE=cut) or powered off
  : > "$work/console.log"
  # cache=writethrough: the guest sees a disk without a volatile write cache, and QEMU completes
  # a write only once it is in the image file. Killing QEMU then loses exactly what the guest had
  # not yet written (its page cache, requests in flight) - a power cut for everything the guest
  # believed flushed. (writeback would also survive a QEMU kill on the host's page cache, but
  # cache=unsafe drops flushes; none needs O_DIRECT, which tmpfs TMPDIRs lack.)
  # ttyS1 carries rig-sim's heartbeat to a Unix socket, read by heartbeat_watch.py as it arrives
  # (which also cuts the power on SIGUSR1 and tells the guest's clock at the cut).
  # The VM stands for the rig's own computer, whose CPUs nothing else uses. On a busy host its
  # vCPU threads otherwise stand still for 200-500 ms at a time while the guest's clock runs
  # (2026-11-28: the recorder's commits started up to 464 ms late): a frozen computer, which no
  # archive design can outrun. So QEMU runs at nice -10 where allowed (as root, as in CI). (Load
  # inside the guest is no substitute: a spinning guest process keeps both vCPU threads busy, and
  # on a 2-core host QEMU's own I/O thread then waits for a core - a 14 ms stall of rigd's loop,
  # 2026-11-28.)
  rm -f "$work/hb.sock" "$work/heartbeat"
  $qemu_nice qemu-system-x86_64 -accel tcg -smp 2 -m 1G $qemu_lock -nographic -no-reboot -nic none \
    -drive "file=$disk,format=raw,if=virtio,cache=writethrough" \
    -chardev "socket,id=hb,path=$work/hb.sock,server=on,wait=off" -serial mon:stdio -serial chardev:hb \
    -kernel "$cache/vmlinux" -initrd "$work/initrd.gz" -append "console=ttyS0 loglevel=3 panic=-1 rigmode=$1" \
    </dev/null > "$work/console.log" 2>&1 &
  qemu=$!
  $qemu_nice python3 "$here/heartbeat_watch.py" "$work/hb.sock" "$qemu" "$work/heartbeat" &
  watcher=$!
  # Every fifth cut falls while the run is armed (the IOP settling, no samples yet), the others
  # while it cuts; a run that ended before cutting (a fault) is cut as it is.
  local waited=0 moment='^CYC [0-9]* [0-9]* \(Cutting\|Retracting\|Done\|Ready\|Fault\|EStop\|Idle\)'
  [ $((boot_no % 5)) -eq 4 ] && moment='^CYC [0-9]* [0-9]'
  while kill -0 "$qemu" 2>/dev/null; do
    if [ "$1" = cut ] && grep -q "$moment" "$work/console.log"; then
      local delay_ms=$(( RANDOM % 1500 ))
      sleep "$(printf '0.%03d' "$delay_ms")"
      kill -USR1 "$watcher" 2>/dev/null || kill -9 "$qemu"   # the watcher kills QEMU (-9)
      { wait "$watcher"; wait "$qemu"; } 2>/dev/null || true   # no "Killed" job notices
      echo "cut $boot_no: ${delay_ms} ms after the run's first status$([ $((boot_no % 5)) -eq 4 ] || echo ' cutting')"
      return 0
    fi
    sleep 0.05; waited=$((waited + 1))
    # A hang guard only: under TCG on a fully busy host a boot took over 5 min to reach its cut.
    [ "$waited" -lt 18000 ] || { tr -d '\r' < "$work/console.log"; echo "FAIL: boot $boot_no timed out"; return 1; }
  done
  { wait "$qemu"; wait "$watcher"; } 2>/dev/null || true
  if [ "$1" = cut ]; then tr -d '\r' < "$work/console.log"; echo "FAIL: boot $boot_no ended before the cut"; return 1; fi
}

# loss FROM_S: the cut run's loss [ms of samples] after loop time FROM_S [s] (its last archived
# sample): lost = up to rig-sim's last DAQ read in the heartbeat (rigd read the DAQ for a sample
# that late), lost_max = up to the guest's clock at the cut (no sample is later). Both on the
# guest's CLOCK_MONOTONIC: loop time + the loop's start (LOOPSTART). Empty without a heartbeat.
loss() {
  lost=""; lost_max=""
  { [ -n "$hb" ] && [ "${hb%% *}" != none ] && [ "${loop_start:--1}" != -1 ]; } || return 0
  read -r lost lost_max < <(echo "$hb" | awk -v s="$loop_start" -v t="$1" \
    '{ a = (s + t) * 1e6; printf "%.1f %.1f\n", ($2 - a) / 1000, ($1 - a) / 1000 }')
}

# judge_loss WHAT FROM_S: measure (loss) and check one cut run's loss against the limit.
judge_loss() {
  loss "$2"
  if [ -z "$lost" ]; then
    echo "FAIL: run $cut_run: $1, but no heartbeat reached the host before the cut ('$hb', loop start '$loop_start')"
    failures=$((failures + 1)); return 0
  fi
  losses="$losses $lost"; losses_max="$losses_max $lost_max"
  echo "run $cut_run: $1, ${lost}..${lost_max} ms lost (heartbeat: $hb)"
  # rigd's tally before the cut (scenario_power.sh COMMITS): longest commit, latest start,
  # longest exposure, last exposure [ms].
  if [ -n "$cut_commits" ]; then
    read -r _ c_max c_late c_exp c_last <<< "$cut_commits"
    echo "run $cut_run: rigd's commits before the cut: longest ${c_max} ms, latest start ${c_late} ms late, exposure longest ${c_exp} ms, last ${c_last} ms"
    commit_max="$commit_max $c_max"; commit_late="$commit_late $c_late"; exposure_max="$exposure_max $c_exp"
  fi
  # A read after the cut would mean the clocks are misjudged by more than a loop period.
  if awk -v a="$lost" -v b="$lost_max" -v p="$period_ms" 'BEGIN { exit !(a > b + p) }'; then
    echo "FAIL: run $cut_run: rig-sim's last read (${lost} ms) is after the guest's clock at the cut (${lost_max} ms)"
    failures=$((failures + 1))
  fi
  if awk -v b="$lost_max" -v l="$limit_ms" -v p="$period_ms" 'BEGIN { exit !(b >= l + p) }'; then
    echo "FAIL: run $cut_run lost up to $lost_max ms of samples (limit: flush interval $limit_ms ms + one $period_ms ms loop period)"
    failures=$((failures + 1))
  fi
}

RANDOM=$seed
qemu_nice=""; qemu_lock=""; [ "$(nice -n -10 nice 2>/dev/null)" -lt "$(nice)" ] && qemu_nice="nice -n -10"
# As root, the rig's computer also gets the CPU and memory a computer of its own would have:
# - a CPU group (cgroup v1 cpu.shares 262144, v2 cpu.weight 10000: ~256x an ordinary process's
#   share; nice -10 alone is ~9x a spinner's, and two spinners, a dsync writer and a memory
#   churner still took the vCPUs' cores for tens of ms, docs/faults.md power loss item 11).
#   Not real-time priority: under TCG the VM keeps both cores busy by itself (QEMU's main loop
#   ~70-100 % of a core, each vCPU 40-70 %), so SCHED_RR hit the kernel's
#   throttling of real-time tasks (50 ms of every second go to ordinary tasks) and its 100 ms
#   round-robin slices (a QEMU I/O thread waiting behind both vCPUs): 4 of 12 cuts over, worst
#   103.5 ms (2026-12-02).
# - its RAM locked (-overcommit mem-lock=on), so the host's memory churn cannot page it out.
if [ -n "$qemu_nice" ]; then
  qemu_lock="-overcommit mem-lock=on"
  for root in /sys/fs/cgroup/cpu /sys/fs/cgroup; do
    if [ -w "$root/cgroup.procs" ] && { [ -f "$root/cpu.shares" ] || grep -qw cpu "$root/cgroup.subtree_control" 2>/dev/null; }; then
      cpu_group="$root/rig-power.$$"; mkdir "$cpu_group" 2>/dev/null || { cpu_group=""; continue; }
      { echo 262144 > "$cpu_group/cpu.shares" || echo 10000 > "$cpu_group/cpu.weight"; } 2>/dev/null || true
      echo $$ > "$cpu_group/cgroup.procs" && break   # QEMU and the heartbeat reader inherit it
      rmdir "$cpu_group"; cpu_group=""
    fi
  done
fi
echo "QEMU at ${qemu_nice:-the default nice (raising it needs root)}${cpu_group:+, in CPU group $cpu_group}${qemu_lock:+, RAM locked}, disk image in $disk_dir"
start=$(date +%s.%N)
# The limit's margin: one loop period (1 kHz). lost_max counts the time from the last sample the
# loop produced to the cut, which holds no sample: 50 samples lost <=> lost_max < 51 ms.
period_ms=1
failures=0; checked=0; accidental=0; losses=""; losses_max=""; drifts=""; lines=""; commit_max=""; commit_late=""; exposure_max=""
: > "$work/kept"   # "id outcome count min max max_t_s" of runs already checked after their cut
cut_run=""; cut_state=""; committed=-1; cut_from=""; loop_start=""; hb=""; cut_commits=""
for boot_no in $(seq 0 "$cuts"); do
  mode=cut; [ "$boot_no" -eq "$cuts" ] && mode=check
  boot "$mode" || exit 1
  log="$(tr -d '\r' < "$work/console.log")"
  # This boot's view of the archive (printed before the new run started).
  integrity="$(echo "$log" | sed -n 's/^INTEGRITY //p' | head -1)"
  [ "$integrity" = "ok " ] || { echo "$log"; echo "FAIL: boot $boot_no: integrity_check: '$integrity'"; exit 1; }
  { echo "$log" | grep '^RUNROW ' || true; } | cut -d' ' -f2- > "$work/rows"
  while read -r id rest; do
    now="$(grep "^$id " "$work/rows" | cut -d' ' -f2- || true)"
    [ "$now" = "$rest" ] || { echo "FAIL: boot $boot_no: run $id was '$rest' after its cut, now '$now'"; failures=$((failures + 1)); }
  done < "$work/kept"
  if [ -n "$cut_run" ]; then
    read -r outcome count first last last_t < <(grep "^$cut_run " "$work/rows" | cut -d' ' -f2-) || true
    checked=$((checked + 1))
    case "$cut_state" in Armed | Cutting | Retracting) in_progress=1 ;; *) in_progress=0 ;; esac
    if [ "$in_progress" = 0 ]; then   # the run had ended (Done, Fault) before the cut
      accidental=$((accidental + 1)); echo "run $cut_run: state '$cut_state' at the cut, not counted"
    elif { [ "${outcome:-}" = completed ] || [ "${outcome:-}" = fault ]; } && [ "$count" -gt 0 ] &&
         [ $((last - first + 1)) -eq "$count" ] && [ "$last" -ge "${committed:--1}" ]; then
      # The run ended before the cut: the last status (a poll 100-400 ms old under TCG) said it
      # was still moving. Its outcome was committed after its last sample, so it is complete.
      accidental=$((accidental + 1)); echo "run $cut_run: '$outcome' with $count contiguous samples: it ended before the cut (last status: '$cut_state'), not counted"
    elif [ "${outcome:-missing}" != interrupted ]; then
      echo "FAIL: run $cut_run (cut while $cut_state) is '${outcome:-missing}' after the restart, not interrupted"
      echo "archive after boot $boot_no (id outcome samples first last last_t_s):"; cat "$work/rows"; failures=$((failures + 1))
    elif [ "${committed:--1}" -ge 0 ] && { [ "$count" -eq 0 ] || [ "$last" -lt "$committed" ]; }; then
      echo "FAIL: run $cut_run lost committed samples: sample $committed was committed before the cut, the archive ends at ${last}"
      failures=$((failures + 1))
    elif [ "$count" -eq 0 ] && [ -n "$cut_from" ]; then   # cut while cutting, no sample archived
      # Cycle N is at loop time N ms or later (the loop skips lost deadlines, never bursts).
      judge_loss "no sample kept though cutting since cycle $cut_from" "$(awk -v c="$cut_from" 'BEGIN { print c / 1000 }')"
    elif [ "$count" -gt 0 ]; then
      [ $((last - first + 1)) -eq "$count" ] || { echo "FAIL: run $cut_run has a gap: $count samples in $first..$last"; failures=$((failures + 1)); }
      judge_loss "$count samples kept (committed before the cut: up to $committed; last at loop time $last_t s)" "$last_t"
    fi
    grep "^$cut_run " "$work/rows" >> "$work/kept" || true
  fi
  [ "$mode" = cut ] || break
  # The last complete status line (the cut may have torn the one being printed).
  status_line="$(echo "$log" | grep '^CYC [0-9]* [0-9]* [A-Za-z]* -\?[0-9][0-9]*$' | tail -1 || true)"
  read -r _ cut_run _ cut_state committed <<< "$status_line"
  cut_commits="$(echo "$log" | grep '^COMMITS [0-9.e+-]* [0-9.e+-]* [0-9.e+-]* [0-9.e+-]*$' | tail -1 || true)"
  cut_from=$(echo "$log" | awk -v r="$cut_run" '$1 == "CYC" && $2 == r && $4 == "Cutting" { print $3; exit }')
  # The clock of this boot (the next boot reads its archive): the loop's start and the heartbeat
  # (heartbeat_watch.py: cut_us last_read_us last_line_us lines window_lines drift_us dropped).
  loop_start="$(echo "$log" | sed -n 's/^LOOPSTART //p' | head -1)"
  hb="$(cat "$work/heartbeat" 2>/dev/null || true)"
  read -r _ _ _ hb_count _ hb_drift _ <<< "$hb" || true
  case "${hb_count:-}" in '' | *[!0-9]*) ;; *) lines="$lines $hb_count"; drifts="$drifts ${hb_drift#-}" ;; esac
done
secs=$(echo "$(date +%s.%N) - $start" | bc)
measured=$(echo $losses | wc -w)
median() { tr ' ' '\n' | grep . | sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
largest() { tr ' ' '\n' | grep . | sort -g | tail -1 | grep . || echo -; }
smallest() { tr ' ' '\n' | grep . | sort -g | head -1 | grep . || echo -; }
echo "POWER LOSS | $cuts power cuts (kill -9 QEMU, seed $seed), $checked cut runs checked, $accidental not cutting at the cut, $measured measured (cutting), every sample committed before the cut kept | loss per cut (ms of samples after the last archived one: at least up to rig-sim's last DAQ read, at most up to the guest's clock at the cut): worst $(echo $losses | largest)..$(echo $losses_max | largest), median $(echo $losses | median)..$(echo $losses_max | median), least $(echo $losses | smallest)..$(echo $losses_max | smallest) (limit $limit_ms + $period_ms) | rigd's commits over a boot (longest commit, latest start, longest exposure; worst and median of boots): $(echo $commit_max | largest)/$(echo $commit_max | median), $(echo $commit_late | largest)/$(echo $commit_late | median), $(echo $exposure_max | largest)/$(echo $exposure_max | median) ms | heartbeat lines per boot: median $(echo $lines | median), clock offset drift over a boot: worst $(echo $drifts | largest) us | integrity_check ok on every boot | $(printf '%.0f' "$secs") s"
# Every cut must have been checked, and most must have cut a run while it cut: a rig
# that faults before it records would pass the checks above without testing anything.
[ "$checked" -eq "$cuts" ] || { echo "FAIL: $checked of $cuts cut runs checked"; failures=$((failures + 1)); }
[ "$measured" -ge $(( cuts / 2 )) ] || { echo "FAIL: only $measured of $cuts cuts hit a cutting run"; failures=$((failures + 1)); }
[ "$failures" -eq 0 ]
