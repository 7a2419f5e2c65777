#pragma once
// What the loop knows at one cycle, and what it asks of the motion controller.
#include "rig/drivers/digital_io.hpp"
#include "run_types.hpp"

namespace rig::rt {

struct CycleInput {
  double t_s = 0.0;              // loop time [s]
  double dt_s = 0.001;           // since the previous cycle [s]
  bool io_ok = true;             // this cycle's reads succeeded
  int consecutive_misses = 0;    // failed DAQ reads in a row
  double unanswered_ms = 0.0;    // on-time cycles without a valid DAQ reply, summed [ms]
  bool link_lost = false;        // unanswered_ms reached safety.link_lost_after_ms
  double raw_position_mm = 0.0;  // calibrated potentiometer, before the homing offset
  double position_mm = 0.0;      // carriage from home (valid once homed)
  double raw_force_N = 0.0;      // calibrated load cell, before tare
  double force_N = 0.0;          // tared force
  double force_volts = 0.0;      // as read, for the stuck-channel check
  double iop_mmHg = 0.0;
  double velocity_mm_s = 0.0;
  drivers::DigitalInputs inputs{};
  bool overrun_storm = false;
  int failed_writes = 0;       // output writes in a row the DAQ refused while it answered reads
  bool write_refused = false;  // the last of them was refused (Modbus exception), not lost
  bool daq_restarted = false;  // the DAQ's conversion counter went backwards this cycle (reboot)
  FaultCode service_fault = FaultCode::kNone;  // raised by a non-RT service (recorder, camera)
};

struct MotionRequest {
  enum class Mode : unsigned char { kOff, kHold, kVelocity, kMoveTo };
  Mode mode = Mode::kOff;
  double velocity_mm_s = 0.0;    // kVelocity
  double target_mm = 0.0;        // kMoveTo
  double speed_mm_s = 0.0;       // kMoveTo
  bool reset_reference = false;  // coordinates changed (homing) or motion (re)starts
};

class EventSink {
 public:
  virtual ~EventSink() = default;
  virtual void emit(const Event& event) noexcept = 0;  // RT-safe: no allocation, no blocking
};

}  // namespace rig::rt
