#!/bin/bash
# Kernel-in-the-loop tier, step 1 (once per machine, cached): Debian's kernel image, the
# gpio-sim module built out of tree (Debian's config lacks GPIO_SIM and IRQ_SIM), and an
# uncompressed vmlinux so QEMU boots it directly (saves the TCG xz decompression, ~2.5 s).
# usage: prepare_kernel.sh CACHE_DIR      -> CACHE_DIR/{kroot,vmlinux,KVER}
# Exit 77 (ctest skip) only when QEMU itself is not installed.
set -euo pipefail
cache="${1:?usage: prepare_kernel.sh CACHE_DIR}"
mkdir -p "$cache"; cache="$(cd "$cache" && pwd)"
command -v qemu-system-x86_64 >/dev/null || { echo "SKIP: qemu-system-x86_64 is not installed (package qemu-system-x86)"; exit 77; }

# The running kernel is not Debian's (containers, CI VMs): use the version linux-image-amd64
# points at, whose headers ./rig installs as linux-headers-amd64.
kver="$(dpkg-query -W -f='${Depends}' linux-headers-amd64 | sed -n 's/.*linux-headers-\([0-9][^ ,]*-amd64\).*/\1/p')"
[ -n "$kver" ] || { echo "FAIL: cannot tell the kernel version from linux-headers-amd64"; exit 1; }
[ -d "/usr/src/linux-headers-$kver" ] || { echo "FAIL: /usr/src/linux-headers-$kver missing (install linux-headers-amd64)"; exit 1; }
if [ -f "$cache/ready" ] && [ "$(cat "$cache/KVER" 2>/dev/null)" = "$kver" ]; then echo "kernel $kver ready in $cache"; exit 0; fi
rm -rf "$cache/kroot" "$cache/gpiosim" "$cache/ready"
cd "$cache"

# 1. Kernel image + modules, unpacked only (nothing touches /boot or the host's modules).
if ! ls linux-image-"$kver"_*.deb >/dev/null 2>&1; then
  apt-get download -q "linux-image-$kver" >/dev/null 2>&1 || { apt-get update -q >/dev/null && apt-get download -q "linux-image-$kver" >/dev/null; }
fi
dpkg-deb -x linux-image-"$kver"_*.deb kroot

# 2. gpio-sim out of tree, with the IRQ simulator linked in. irq_to_desc() is not exported
#    to modules in 6.1, so the one call that needs it goes through generic_handle_irq().
src=/usr/src/linux-source-6.1.tar.xz
[ -f "$src" ] || { echo "FAIL: $src missing (install linux-source-6.1)"; exit 1; }
mkdir -p gpiosim/mod
tar -xJf "$src" -C gpiosim --strip-components=1 linux-source-6.1/drivers/gpio/gpio-sim.c \
  linux-source-6.1/drivers/gpio/gpiolib.h linux-source-6.1/kernel/irq/irq_sim.c
cp gpiosim/drivers/gpio/gpio-sim.c gpiosim/mod/gpio-sim-main.c
cp gpiosim/drivers/gpio/gpiolib.h gpiosim/kernel/irq/irq_sim.c gpiosim/mod/
sed -i 's/handle_simple_irq(irq_to_desc(irqnum));/generic_handle_irq(irqnum);/' gpiosim/mod/irq_sim.c
grep -q 'generic_handle_irq(irqnum)' gpiosim/mod/irq_sim.c || { echo "FAIL: irq_sim.c patch did not apply"; exit 1; }
printf 'obj-m := gpio-sim.o\ngpio-sim-y := gpio-sim-main.o irq_sim.o\n' > gpiosim/mod/Kbuild
make -s -C "/usr/src/linux-headers-$kver" M="$cache/gpiosim/mod" modules >gpiosim/build.log 2>&1 || { cat gpiosim/build.log; exit 1; }
mkdir -p "kroot/lib/modules/$kver/extra" && cp gpiosim/mod/gpio-sim.ko "kroot/lib/modules/$kver/extra/"
depmod -b kroot "$kver"

# 3. Uncompressed kernel for QEMU's direct (PVH) boot.
python3 - "kroot/boot/vmlinuz-$kver" > vmlinux.xz <<'PY'
import sys
data = open(sys.argv[1], 'rb').read()
start = data.find(b'\xfd7zXZ\x00')
if start < 0: sys.exit("no xz payload in " + sys.argv[1])
sys.stdout.buffer.write(data[start:])
PY
xz -dc vmlinux.xz > vmlinux 2>/dev/null || true   # trailing bytes after the xz stream are expected
rm -f vmlinux.xz
[ -s vmlinux ] || { echo "FAIL: could not extract vmlinux from vmlinuz-$kver"; exit 1; }
echo "$kver" > KVER
touch ready
echo "kernel $kver prepared in $cache"
