# Inside the VM: a gpio-sim chip with 8 lines, then the GPIO tests against it.
set -u
modprobe gpio-sim || exit 1
G=/sys/kernel/config/gpio-sim/rig
mkdir $G $G/bank0 && echo 8 > $G/bank0/num_lines && echo 1 > $G/live || exit 1
export RIG_GPIO_CHIP=$(cat $G/bank0/chip_name)
DEV=$(cat $G/dev_name)
export RIG_GPIO_SIM_SYSFS=$(dirname $(find /sys/devices/platform/$DEV/ -name sim_gpio0 | head -1))
echo "gpio-sim: chip $RIG_GPIO_CHIP, lines in $RIG_GPIO_SIM_SYSFS"
kernel_gpio_test --gtest_color=no
