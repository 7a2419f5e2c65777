#!/bin/bash
# Kernel-in-the-loop tier, step 2: boot Debian's kernel under QEMU with a busybox initramfs
# that holds the given kernel modules, programs (with their shared libraries) and a scenario
# script, run the script as PID 1's child and pass its exit code back.
# usage: run_in_vm.sh CACHE_DIR SCENARIO.sh "module module..." PROGRAM...
# Exit 77 (ctest skip) only when QEMU cannot run at all.
set -euo pipefail
cache="$1"; scenario="$2"; mods="$3"; shift 3
here="$(cd "$(dirname "$0")" && pwd)"
command -v qemu-system-x86_64 >/dev/null || { echo "SKIP: qemu-system-x86_64 is not installed"; exit 77; }
[ -f "$cache/ready" ] || { echo "FAIL: $cache is not prepared (prepare_kernel.sh)"; exit 1; }
work="$(mktemp -d "${TMPDIR:-/tmp}/rig-vm.XXXXXX")"; trap 'rm -rf "$work"' EXIT
"$here/build_initramfs.sh" "$cache" "$work" "$scenario" "$mods" "$@"

accel=tcg
[ -w /dev/kvm ] && [ "${RIG_TRY_KVM:-0}" = 1 ] && accel=kvm   # KVM is broken on the CI VMs
# The VM stands for a machine of its own: on a busy host its vCPUs otherwise stand still for
# hundreds of ms (docs/faults.md, power loss item 9), so QEMU runs at nice -10 where allowed.
qemu_nice=""; [ "$(nice -n -10 nice 2>/dev/null)" -lt "$(nice)" ] && qemu_nice="nice -n -10"
start=$(date +%s.%N)
set +e
timeout "${RIG_VM_TIMEOUT:-240}" $qemu_nice qemu-system-x86_64 -accel "$accel" -smp 2 -m 1G -nographic -no-reboot -nic none \
  -kernel "$cache/vmlinux" -initrd "$work/initrd.gz" -append 'console=ttyS0 loglevel=3 panic=-1' </dev/null > "$work/console.log" 2>&1
qemu_rc=$?
set -e
tr -d '\r' < "$work/console.log"
echo "VM wall time: $(echo "$(date +%s.%N) - $start" | bc) s (accel=$accel, qemu exit $qemu_rc)"
if [ "$qemu_rc" -ne 0 ] && ! grep -q 'TEST-RC=' "$work/console.log"; then
  grep -qi 'could not\|failed to initialize' "$work/console.log" && { echo "SKIP: QEMU cannot run on this machine"; exit 77; }
  echo "FAIL: the VM did not finish (qemu exit $qemu_rc)"; exit 1
fi
grep -q 'TEST-RC=0' "$work/console.log"
