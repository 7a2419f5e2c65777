#pragma once
// Haptic device (Phantom via OpenHaptics, or simulated). The servo loop owns the
// device: begin_frame/read position/set force/end_frame once per 1 ms tick.
#include <array>
#include <string>

#include "rig/drivers/io_status.hpp"

namespace rig::drivers {

using Vec3 = std::array<double, 3>;

struct HapticLimits {
  double max_force_N = 0.0;             // HD_NOMINAL_MAX_FORCE
  double max_continuous_force_N = 0.0;  // HD_NOMINAL_MAX_CONTINUOUS_FORCE
  double max_stiffness_N_per_mm = 0.0;  // HD_NOMINAL_MAX_STIFFNESS
};

enum class HapticFault : std::uint8_t { kNone, kWarmMotors, kExceededMaxForce, kExceededMaxVelocity,
                                        kCommError, kOther };

class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  virtual std::string describe() const = 0;
  virtual HapticLimits limits() const noexcept = 0;
  // One servo tick: reads the end-effector position [mm] and applies force [N].
  virtual IoStatus read_position(Vec3& position_mm) noexcept = 0;
  virtual IoStatus write_force(const Vec3& force_N) noexcept = 0;
  // Latest device fault (cleared by reading it); any fault means force off.
  virtual HapticFault take_fault() noexcept = 0;
};

}  // namespace rig::drivers
