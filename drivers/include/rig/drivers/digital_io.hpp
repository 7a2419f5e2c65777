#pragma once
// Digital lines: limit switches and e-stop in, motor-enable relay and camera trigger out.
#include "rig/drivers/io_status.hpp"

namespace rig::drivers {

struct DigitalInputs {
  bool home_limit = false;   // carriage at its home end stop
  bool end_limit = false;    // carriage at the far end stop (towards the eye)
  bool estop = false;        // e-stop button pressed (or its loop broken)
  bool drive_fault = false;  // motor drive reports a fault
  // The DAQ's communication watchdog forced its outputs off since rigd's last write (no
  // write for daq.watchdog_ms): the motor stopped without rigd commanding it.
  bool daq_watchdog_tripped = false;
};

struct DigitalOutputs {
  bool motor_enable = false;    // hardware enable relay of the motor drive
  bool camera_trigger = false;  // rising edge starts an exposure
};

class DigitalIo {
 public:
  virtual ~DigitalIo() = default;
  virtual IoStatus read(DigitalInputs& inputs) noexcept = 0;
  virtual IoStatus write(const DigitalOutputs& outputs) noexcept = 0;
};

}  // namespace rig::drivers
