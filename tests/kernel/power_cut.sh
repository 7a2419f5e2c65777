#!/bin/bash
# Power loss: rigd records runs against rig-sim inside the VM, its SQLite archive on a virtio
# disk (ext4); the host cuts the VM's power (kill -9 QEMU) at a seeded random moment of each
# run, boots again and checks the archive: integrity_check ok, every earlier run unchanged,
# the cut run `interrupted` with contiguous samples and at most one flush interval of samples
# lost (archive.flush_interval_ms of RIGD_CONFIG). Prints a "POWER LOSS |" figure line.
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
  local waited=0
  while kill -0 "$qemu" 2>/dev/null; do
    if [ "$1" = cut ] && grep -q '^CYC [0-9]* [0-9]' "$work/console.log"; then
      local delay_ms=$(( RANDOM % 1500 ))
      sleep "$(printf '0.%03d' "$delay_ms")"
      kill -9 "$qemu"; wait "$qemu" 2>/dev/null || true
      echo "cut $boot_no: ${delay_ms} ms after the run's first status"
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
failures=0; worst_ms=0; checked=0; accidental=0
: > "$work/kept"   # "id outcome count min max" of runs already checked after their cut
cut_run=""; last_cycles=""; cut_state=""
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
    elif [ "$count" -gt 0 ]; then
      [ $((last - first + 1)) -eq "$count" ] || { echo "FAIL: run $cut_run has a gap: $count samples in $first..$last"; failures=$((failures + 1)); }
      lost=$(( last_cycles - (last + 1) ))   # 1 ms per cycle; cycles as last seen before the cut
      [ "$lost" -gt "$worst_ms" ] && worst_ms=$lost
      echo "run $cut_run: $count samples kept, ${lost} ms lost after the last status seen"
      [ "$lost" -le "$limit_ms" ] || { echo "FAIL: run $cut_run lost $lost ms (limit $limit_ms)"; failures=$((failures + 1)); }
    fi
    grep "^$cut_run " "$work/rows" >> "$work/kept" || true
  fi
  [ "$mode" = cut ] || break
  status_line="$(echo "$log" | grep '^CYC [0-9]* [0-9]' | tail -1 || true)"
  read -r _ cut_run last_cycles cut_state <<< "$status_line"
done
secs=$(echo "$(date +%s.%N) - $start" | bc)
echo "POWER LOSS | $cuts power cuts (kill -9 QEMU, seed $seed), $checked cut runs checked, $accidental not cutting at the cut | worst loss $worst_ms ms of samples (limit $limit_ms) | integrity_check ok on every boot | $(printf '%.0f' "$secs") s"
[ "$failures" -eq 0 ]
