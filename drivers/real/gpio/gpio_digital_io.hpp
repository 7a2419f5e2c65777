#pragma once
// DigitalIo on GPIO lines: home and end limit switches, e-stop and (optionally) the drive's
// fault output as debounced edge-event inputs; motor enable and camera trigger as outputs.
// While the e-stop input is active the motor-enable line is held off here, whatever the
// loop asks: a second, independent stop next to the loop's own interlock.
#include <cstdint>
#include <memory>
#include <string>

#include "gpio_line_bank.hpp"
#include "input_debouncer.hpp"
#include "rig/drivers/digital_io.hpp"
#include "rig/drivers/loop_clock.hpp"

namespace rig::drivers {

struct GpioSettings {
  std::string chip = "gpiochip0";  // name, /dev path, label or number
  unsigned home_line = 0;
  unsigned end_line = 1;
  unsigned estop_line = 2;
  int drive_fault_line = -1;  // -1 = not wired
  unsigned motor_enable_line = 3;
  unsigned camera_trigger_line = 4;
  bool estop_active_low = true;  // normally-closed e-stop loop: a broken wire reads as pressed
  bool limits_active_low = false;
  std::int64_t debounce_ns = 2'000'000;
};

// Input and output order of the bank GpioDigitalIo expects.
enum GpioInput : std::size_t {
  kHomeInput = 0,
  kEndInput = 1,
  kEstopInput = 2,
  kDriveFaultInput = 3
};
enum GpioOutput : std::size_t { kMotorEnableOutput = 0, kCameraTriggerOutput = 1 };

class GpioDigitalIo final : public DigitalIo {
 public:
  // Opens the chip through libgpiod (v1 API); throws naming the chip and line (setup only).
  GpioDigitalIo(const GpioSettings& settings, LoopClock& clock);
  // Any bank with inputs {home, end, e-stop[, drive fault]} and outputs {enable, trigger}.
  GpioDigitalIo(std::unique_ptr<GpioLineBank> bank, bool has_drive_fault, std::int64_t debounce_ns,
                LoopClock& clock);

  IoStatus read(DigitalInputs& inputs) noexcept override;
  IoStatus write(const DigitalOutputs& outputs) noexcept override;
  std::uint64_t edges_seen() const noexcept { return edges_seen_; }

 private:
  std::unique_ptr<GpioLineBank> bank_;
  bool has_drive_fault_;
  LoopClock* clock_;
  InputDebouncer debouncer_;
  bool estop_active_ = true;  // until the first read proves otherwise
  DigitalOutputs last_outputs_{};
  bool outputs_written_ = false;
  std::uint64_t edges_seen_ = 0;
};

}  // namespace rig::drivers
