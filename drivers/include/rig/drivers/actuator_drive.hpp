#pragma once
// Motor drive (DC motor on the lead screw) and the pump of the IOP line: the DAQ's
// analog outputs. enable=false must remove motor power at the drive.
#include "rig/drivers/io_status.hpp"

namespace rig::drivers {

struct DriveCommand {
  bool motor_enable = false;
  double motor_volts = 0.0;   // armature voltage command [V], sign = direction (+ into the eye)
  double pump_command = 0.0;  // IOP pump drive, fraction of full flow [0..1]
};

class ActuatorDrive {
 public:
  virtual ~ActuatorDrive() = default;
  virtual IoStatus write(const DriveCommand& command) noexcept = 0;
};

}  // namespace rig::drivers
