# Inside the VM: dummy_hcd (a host and a device controller joined in software), a gadget
# with one FunctionFS function served by rig-usb-gadget, then the USB DAQ tests as host.
set -u
modprobe dummy_hcd && modprobe usb_f_fs || exit 1
U=/sys/kernel/config/usb_gadget/rig
mkdir $U && cd $U || exit 1
echo 0x1d6b > idVendor; echo 0x0104 > idProduct
mkdir strings/0x409; echo rigd > strings/0x409/manufacturer; echo "rig USB DAQ (simulated)" > strings/0x409/product
echo SIM0001 > strings/0x409/serialnumber
mkdir configs/c.1 functions/ffs.daq && ln -s functions/ffs.daq configs/c.1/
cd /
mkdir -p /dev/ffs-daq && mount -t functionfs daq /dev/ffs-daq || exit 1
rig-usb-gadget /dev/ffs-daq & GADGET=$!
for i in $(seq 100); do [ -e /dev/ffs-daq/ep2 ] && break; sleep 0.1; done
export RIG_UDC=$(ls /sys/class/udc | head -1)
echo "$RIG_UDC" > $U/UDC || exit 1
for i in $(seq 100); do grep -qs 0104 /sys/bus/usb/devices/*/idProduct && break; sleep 0.1; done
export RIG_USB_GADGET_DIR=$U
kernel_usb_test --gtest_color=no; rc=$?
kill $GADGET
exit $rc
