#!/bin/bash
# Power loss: rigd records runs against rig-sim inside the VM, its SQLite archive on a virtio
# disk (ext4); the host cuts the VM's power (kill -9 QEMU) at a seeded random moment of each
# run (0-1.5 s into cutting; every fifth while armed), boots again and checks the archive:
# integrity_check ok, every earlier run unchanged, the cut run `interrupted` with contiguous
# samples and at most one flush interval of samples lost (archive.flush_interval_ms of
# RIGD_CONFIG). Fails too unless every cut was checked and at least half hit a run while it
# cut. Prints a "POWER LOSS |" figure line.
# usage: power_cut.sh CACHE_DIR CUTS SEED RIGD_CONFIG MODEL_FILE PROGRAM...
set -euo pipefail
cache="$1"; cuts="$2"; seed="$3"; config="$4"; model="$5"; shift 5
limit_ms="$(sed -n 's/^flush_interval_ms *= *\([0-9]*\).*/\1/p' "$config")"
[ -n "$limit_ms" ] || { echo "FAIL: $config has no archive.flush_interval_ms"; exit 1; }
here="$(cd "$(dirname "$0")" && pwd)"
command -v qemu-system-x86_64 >/dev/null || { echo "SKIP: qemu-system-x86_64 is not installed"; exit 77; }
[ -f "$cache/ready" ] || { echo "FAIL: $cache is not prepared (prepare_kernel.sh)"; exit 1; }
work="$(mktemp -d "${TMPDIR:-/tmp}/rig-power.XXXXXX")"; trap 'kill -9 $qemu 2>/dev/null || true; rm -rf "$work"' EXIT
qemu=""
"$here/build_initramfs.sh" "$cache" "$work" "$here/scenario_power.sh" "virtio_pci virtio_blk ext4 crc32c_generic" "$@" "$(command -v sqlite3)" "$(command -v chrt)"
# rigd's config and model ride in a second cpio appended to the first (the kernel unpacks both).
mkdir -p "$work/extra/etc/rig" && cp "$config" "$model" "$work/extra/etc/rig/"
(cd "$work/extra" && find . | cpio -o -H newc --quiet | gzip -1 >> "$work/initrd.gz")
disk="$work/archive.img"
truncate -s 64M "$disk" && mkfs.ext4 -q -F "$disk"

boot() {  # boot MODE -> $work/console.log; returns once the VM is cut (MODE=cut) or powered off
  : > "$work/console.log"
  # cache=writethrough: the guest sees a disk without a volatile write cache, and QEMU completes
  # a write only once it is in the image file. Killing QEMU then loses exactly what the guest had
  # not yet written (its page cache, requests in flight) - a power cut for everything the guest
  # believed flushed. (writeback would also survive a QEMU kill on the host's page cache, but
  # cache=unsafe drops flushes; none needs O_DIRECT, which tmpfs TMPDIRs lack.)
  qemu-system-x86_64 -accel tcg -smp 2 -m 1G -nographic -no-reboot -nic none \
    -drive "file=$disk,format=raw,if=virtio,cache=writethrough" \
    -kernel "$cache/vmlinux" -initrd "$work/initrd.gz" -append "console=ttyS0 loglevel=3 panic=-1 rigmode=$1" \
    </dev/null > "$work/console.log" 2>&1 &
  qemu=$!
  # Every fifth cut falls while the run is armed (the IOP settling, no samples yet), the others
  # while it cuts; a run that ended before cutting (a fault) is cut as it is.
  local waited=0 moment='^CYC [0-9]* [0-9]* \(Cutting\|Retracting\|Done\|Ready\|Fault\|EStop\|Idle\)'
  [ $((boot_no % 5)) -eq 4 ] && moment='^CYC [0-9]* [0-9]'
  while kill -0 "$qemu" 2>/dev/null; do
    if [ "$1" = cut ] && grep -q "$moment" "$work/console.log"; then
      local delay_ms=$(( RANDOM % 1500 ))
      sleep "$(printf '0.%03d' "$delay_ms")"
      kill -9 "$qemu"; wait "$qemu" 2>/dev/null || true
      echo "cut $boot_no: ${delay_ms} ms after the run's first status$([ $((boot_no % 5)) -eq 4 ] || echo ' cutting')"
      return 0
    fi
    sleep 0.05; waited=$((waited + 1))
    [ "$waited" -lt 3600 ] || { tr -d '\r' < "$work/console.log"; echo "FAIL: boot $boot_no timed out"; return 1; }
  done
  wait "$qemu" 2>/dev/null || true
  if [ "$1" = cut ]; then tr -d '\r' < "$work/console.log"; echo "FAIL: boot $boot_no ended before the cut"; return 1; fi
}

RANDOM=$seed
start=$(date +%s.%N)
failures=0; worst_ms=0; worst_max_ms=0; checked=0; accidental=0; losses=""; losses_max=""
: > "$work/kept"   # "id outcome count min max" of runs already checked after their cut
cut_run=""; last_cycles=""; cut_state=""; committed=-1; step=0; cut_from=""
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
    read -r outcome count first last < <(grep "^$cut_run " "$work/rows" | cut -d' ' -f2-) || true
    checked=$((checked + 1))
    case "$cut_state" in Armed | Cutting | Retracting) in_progress=1 ;; *) in_progress=0 ;; esac
    if [ "$in_progress" = 0 ]; then   # the run had ended (Done, Fault) before the cut
      accidental=$((accidental + 1)); echo "run $cut_run: state '$cut_state' at the cut, not counted"
    elif [ "${outcome:-missing}" != interrupted ]; then
      echo "FAIL: run $cut_run (cut while $cut_state) is '${outcome:-missing}' after the restart, not interrupted"
      echo "archive after boot $boot_no (id outcome samples first last):"; cat "$work/rows"; failures=$((failures + 1))
    elif [ "${committed:--1}" -ge 0 ] && { [ "$count" -eq 0 ] || [ "$last" -lt "$committed" ]; }; then
      echo "FAIL: run $cut_run lost committed samples: sample $committed was committed before the cut, the archive ends at ${last}"
      failures=$((failures + 1))
    elif [ "$count" -eq 0 ] && [ -n "$cut_from" ]; then   # cut while cutting, no sample archived
      lost=$(( last_cycles - cut_from )); lost_max=$(( last_cycles + step - cut_from ))
      [ "$lost" -gt "$worst_ms" ] && worst_ms=$lost
      [ "$lost_max" -gt "$worst_max_ms" ] && worst_max_ms=$lost_max
      losses="$losses $lost"; losses_max="$losses_max $lost_max"
      echo "run $cut_run: no sample kept though cutting since cycle $cut_from, ${lost}..${lost_max} ms lost"
      [ "$lost" -le "$limit_ms" ] || { echo "FAIL: run $cut_run lost $lost ms (limit $limit_ms)"; failures=$((failures + 1)); }
    elif [ "$count" -gt 0 ]; then
      [ $((last - first + 1)) -eq "$count" ] || { echo "FAIL: run $cut_run has a gap: $count samples in $first..$last"; failures=$((failures + 1)); }
      # Loss in loop cycles (1 ms each) between the last archived sample and the loop's cycle at
      # the cut, which lies between the last status the host saw and that plus the largest
      # step between two status lines of this run (the console shows a status a poll late).
      lost=$(( last_cycles - (last + 1) )); lost_max=$(( last_cycles + step - (last + 1) ))
      [ "$lost" -gt "$worst_ms" ] && worst_ms=$lost
      [ "$lost_max" -gt "$worst_max_ms" ] && worst_max_ms=$lost_max
      losses="$losses $lost"; losses_max="$losses_max $lost_max"
      echo "run $cut_run: $count samples kept (committed before the cut: up to $committed), ${lost}..${lost_max} ms lost"
      [ "$lost" -le "$limit_ms" ] || { echo "FAIL: run $cut_run lost $lost ms (limit $limit_ms)"; failures=$((failures + 1)); }
    fi
    grep "^$cut_run " "$work/rows" >> "$work/kept" || true
  fi
  [ "$mode" = cut ] || break
  # The last complete status line (the cut may have torn the one being printed).
  status_line="$(echo "$log" | grep '^CYC [0-9]* [0-9]* [A-Za-z]* -\?[0-9][0-9]*$' | tail -1 || true)"
  read -r _ cut_run last_cycles cut_state committed <<< "$status_line"
  cut_from=$(echo "$log" | awk -v r="$cut_run" '$1 == "CYC" && $2 == r && $4 == "Cutting" { print $3; exit }')
  step=$(echo "$log" | awk -v r="$cut_run" '$1 == "CYC" && $2 == r && $3 ~ /^[0-9]+$/ { if (p != "" && $3 - p > m) m = $3 - p; p = $3 } END { print m + 0 }')
done
secs=$(echo "$(date +%s.%N) - $start" | bc)
measured=$(echo $losses | wc -w)
median() { tr ' ' '\n' | grep . | sort -n | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "POWER LOSS | $cuts power cuts (kill -9 QEMU, seed $seed), $checked cut runs checked, $accidental not cutting at the cut, $measured measured (cutting), every sample committed before the cut kept | loss per cut (ms of samples, at least..at most): worst $worst_ms..$worst_max_ms, median $(echo $losses | median)..$(echo $losses_max | median) (limit $limit_ms) | integrity_check ok on every boot | $(printf '%.0f' "$secs") s"
# Every cut must have been checked, and most must have cut a run while it cut: a rig
# that faults before it records would pass the checks above without testing anything.
[ "$checked" -eq "$cuts" ] || { echo "FAIL: $checked of $cuts cut runs checked"; failures=$((failures + 1)); }
[ "$measured" -ge $(( cuts / 2 )) ] || { echo "FAIL: only $measured of $cuts cuts hit a cutting run"; failures=$((failures + 1)); }
[ "$failures" -eq 0 ]
