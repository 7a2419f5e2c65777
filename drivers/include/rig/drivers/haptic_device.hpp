#pragma once
// Haptic device (Phantom via OpenHaptics, or simulated). The device owns the servo clock
// (OpenHaptics' scheduler calls back at 1 kHz; the simulated device runs its own RT
// thread): each tick it hands the end-effector position to the servo and applies the force
// it returns.
#include <array>
#include <cstdint>
#include <string>

namespace rig::drivers {

using Vec3 = std::array<double, 3>;

struct HapticLimits {
  double max_force_N = 0.0;             // HD_NOMINAL_MAX_FORCE
  double max_continuous_force_N = 0.0;  // HD_NOMINAL_MAX_CONTINUOUS_FORCE
  double max_stiffness_N_per_mm = 0.0;  // HD_NOMINAL_MAX_STIFFNESS
};

enum class HapticFault : std::uint8_t {
  kNone,
  kWarmMotors,
  kExceededMaxForce,
  kExceededMaxVelocity,
  kCommError,
  kOther
};
inline const char* to_string(HapticFault fault) noexcept {
  switch (fault) {
    case HapticFault::kNone:
      return "none";
    case HapticFault::kWarmMotors:
      return "motors too warm (HD_WARM_MOTORS): force off, let the device cool";
    case HapticFault::kExceededMaxForce:
      return "maximum force exceeded (HD_EXCEEDED_MAX_FORCE): force off";
    case HapticFault::kExceededMaxVelocity:
      return "maximum velocity exceeded (HD_EXCEEDED_MAX_VELOCITY): force off";
    case HapticFault::kCommError:
      return "device communication error (HD_COMM_ERROR): force off, check the cable";
    case HapticFault::kOther:
      return "device error: force off";
  }
  return "unknown";
}

class HapticServo {
 public:
  virtual ~HapticServo() = default;
  // One servo tick on the device's real-time thread: position [mm] in, force [N] out.
  virtual Vec3 tick(const Vec3& position_mm, double t_s) noexcept = 0;
  // The device reported an error: force is already off.
  virtual void device_fault(HapticFault fault) noexcept = 0;
};

class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  virtual std::string describe() const = 0;
  virtual HapticLimits limits() const noexcept = 0;  // read from the device at run time
  virtual void start(HapticServo& servo) = 0;        // setup: throws with a clear message
  virtual void stop() noexcept = 0;
  virtual void force_off() noexcept = 0;  // safety: zero force now, from any thread
  virtual std::uint64_t ticks() const noexcept = 0;
  virtual bool running() const noexcept = 0;  // the servo is being called
  // Time from the servo's force command to that force at the hand [s] (transport and
  // amplifier lag), so the servo can predict the position it renders for.
  virtual double output_latency_s() const noexcept = 0;
  virtual double period_s() const noexcept = 0;  // servo period [s]
  // True when the servo runs on the wall clock, where a hand may hold the device (and a
  // stalled servo must turn force off); false on a simulated device's virtual clock.
  virtual bool paced_by_wall_clock() const noexcept = 0;
};

}  // namespace rig::drivers
