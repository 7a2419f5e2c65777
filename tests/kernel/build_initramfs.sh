#!/bin/bash
# Kernel-in-the-loop tier: the busybox initramfs for one VM run, with the given kernel modules
# (and their dependencies), programs (with their shared libraries) and scenario script.
# usage: build_initramfs.sh CACHE_DIR WORK_DIR SCENARIO.sh "module module..." PROGRAM...
#        -> WORK_DIR/initrd.gz
set -euo pipefail
cache="$1"; work="$2"; scenario="$3"; mods="$4"; shift 4
here="$(cd "$(dirname "$0")" && pwd)"
kver="$(cat "$cache/KVER")"; kroot="$cache/kroot"
root="$work/root"
mkdir -p "$root"/{bin,sbin,proc,sys,dev,tmp,etc,usr/bin,lib/modules/"$kver"}
cp /bin/busybox "$root/bin/busybox"

# Modules and their dependency closure, from the image's modules.dep.
need=""
for m in $mods; do
  line="$(grep -E "/$m\.ko(\.[a-z]+)?:" "$kroot/lib/modules/$kver/modules.dep")" || { echo "FAIL: module $m not in the kernel image"; exit 1; }
  need="$need ${line%%:*} ${line#*:}"
done
for f in $(echo "$need" | tr ' ' '\n' | sort -u); do
  mkdir -p "$root/lib/modules/$kver/$(dirname "$f")"; cp "$kroot/lib/modules/$kver/$f" "$root/lib/modules/$kver/$f"
done
cp "$kroot/lib/modules/$kver"/modules.{order,builtin,builtin.modinfo} "$root/lib/modules/$kver/"
depmod -b "$root" "$kver"

# Programs and the shared libraries they load.
for program in "$@"; do
  [ -x "$program" ] || { echo "FAIL: $program is not built"; exit 1; }
  cp "$program" "$root/usr/bin/"
  for lib in $(ldd "$program" | grep -o '/[^ ]*'); do mkdir -p "$root$(dirname "$lib")"; cp -nL "$lib" "$root$lib"; done
done
cp "$here/vm_init.sh" "$root/init"; cp "$scenario" "$root/test.sh"; chmod +x "$root/init" "$root/test.sh"
(cd "$root" && find . | cpio -o -H newc --quiet | gzip -1 > "$work/initrd.gz")
