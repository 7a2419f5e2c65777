# Inside the VM: one vivid capture device, then the V4L2 tests against it.
set -u
modprobe vivid n_devs=1 node_types=0x1 || exit 1
export RIG_VIDEO=/dev/video0
for i in $(seq 50); do [ -e $RIG_VIDEO ] && break; sleep 0.1; done
kernel_v4l2_test --gtest_color=no
