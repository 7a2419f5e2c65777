#include "gpio_digital_io.hpp"

#include <array>
#include <vector>

#include "gpiod_v1_line_bank.hpp"

namespace rig::drivers {
namespace {

std::unique_ptr<GpioLineBank> open_bank(const GpioSettings& s) {
  std::vector<GpioLineSpec> inputs{{s.home_line, s.limits_active_low, "home limit"},
                                   {s.end_line, s.limits_active_low, "end limit"},
                                   {s.estop_line, s.estop_active_low, "e-stop"}};
  if (s.drive_fault_line >= 0)
    inputs.push_back({static_cast<unsigned>(s.drive_fault_line), false, "drive fault"});
  const std::vector<GpioLineSpec> outputs{{s.motor_enable_line, false, "motor enable"},
                                          {s.camera_trigger_line, false, "camera trigger"}};
  return std::make_unique<GpiodV1LineBank>(s.chip, inputs, outputs);
}

}  // namespace

GpioDigitalIo::GpioDigitalIo(const GpioSettings& settings, LoopClock& clock)
    : GpioDigitalIo(open_bank(settings), settings.drive_fault_line >= 0, settings.debounce_ns,
                    clock) {}

GpioDigitalIo::GpioDigitalIo(std::unique_ptr<GpioLineBank> bank, bool has_drive_fault,
                             std::int64_t debounce_ns, LoopClock& clock)
    : bank_(std::move(bank)),
      has_drive_fault_(has_drive_fault),
      clock_(&clock),
      debouncer_(debounce_ns) {
  std::array<bool, 4> levels{};
  bank_->read_levels(std::span<bool>(levels.data(), has_drive_fault_ ? 4 : 3));
  debouncer_.reset(levels, clock_->now_ns());
}

IoStatus GpioDigitalIo::read(DigitalInputs& inputs) noexcept {
  std::array<LineEdge, 32> edges{};
  std::size_t count = 0;
  IoStatus status = IoStatus::kOk;
  do {  // drain the kernel's queue: a burst of contact bounce can exceed one batch
    status = bank_->poll_edges(edges, count);
    for (std::size_t i = 0; i < count; ++i)
      debouncer_.on_edge(edges[i].input, edges[i].active, edges[i].timestamp_ns);
    edges_seen_ += count;
  } while (status == IoStatus::kOk && count == edges.size());
  const std::int64_t now = clock_->now_ns();
  inputs.home_limit = debouncer_.read(kHomeInput, now);
  inputs.end_limit = debouncer_.read(kEndInput, now);
  inputs.estop = debouncer_.read(kEstopInput, now);
  inputs.drive_fault = has_drive_fault_ && debouncer_.read(kDriveFaultInput, now);
  if (status != IoStatus::kOk)
    inputs.estop = true;  // a GPIO chip we cannot read is a pressed e-stop
  estop_active_ = inputs.estop;
  if (estop_active_ && last_outputs_.motor_enable) {
    bank_->set_output(kMotorEnableOutput, false);  // cut power now, before the loop's own answer
    last_outputs_.motor_enable = false;
  }
  return status;
}

IoStatus GpioDigitalIo::write(const DigitalOutputs& outputs) noexcept {
  DigitalOutputs wanted = outputs;
  if (estop_active_) wanted.motor_enable = false;
  IoStatus status = IoStatus::kOk;
  if (!outputs_written_ || wanted.motor_enable != last_outputs_.motor_enable)
    status = bank_->set_output(kMotorEnableOutput, wanted.motor_enable);
  if (!outputs_written_ || wanted.camera_trigger != last_outputs_.camera_trigger) {
    const IoStatus trigger = bank_->set_output(kCameraTriggerOutput, wanted.camera_trigger);
    if (status == IoStatus::kOk) status = trigger;
  }
  last_outputs_ = wanted;
  outputs_written_ = true;
  return status;
}

}  // namespace rig::drivers
