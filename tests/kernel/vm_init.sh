#!/bin/busybox sh
# PID 1 of the test VM: mount the kernel's file systems, run the scenario, power off.
/bin/busybox --install -s /bin
export PATH=/bin:/sbin:/usr/bin:/usr/sbin
mount -t proc proc /proc; mount -t sysfs sys /sys; mount -t devtmpfs dev /dev; mount -t tmpfs tmp /tmp
modprobe configfs 2>/dev/null && mount -t configfs none /sys/kernel/config
echo "=== VM up at $(cut -d' ' -f1 /proc/uptime) s"
cd /tmp && sh /test.sh; rc=$?
echo "=== TEST-RC=$rc at $(cut -d' ' -f1 /proc/uptime) s"
poweroff -f
