#pragma once
// Analog inputs of the DAQ: load cell, linear potentiometer, IOP transducer.
// Values are the DAQ's volts; calibration to engineering units happens in the loop.
#include <cstdint>

#include "rig/drivers/io_status.hpp"

namespace rig::drivers {

struct AnalogFrame {
  double force_volts = 0.0;     // load cell bridge amplifier output [V]
  double position_volts = 0.0;  // linear potentiometer wiper [V]
  double iop_volts = 0.0;       // pressure transducer on the IOP line [V]
  std::uint32_t sequence = 0;   // DAQ conversion counter; detects stale reads
};

class AnalogInput {
 public:
  virtual ~AnalogInput() = default;
  // One conversion of every channel. Cyclic: never throws, never blocks longer than the
  // time-out configured at setup.
  virtual IoStatus read(AnalogFrame& frame) noexcept = 0;
};

}  // namespace rig::drivers
