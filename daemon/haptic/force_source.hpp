#pragma once
// What the trainee feels: the force on the keratome for a tip depth [mm] from the corneal
// surface, the deepest point reached so far (front) [mm] and the tip velocity [mm/s].
// Called from the servo tick: no allocation, no blocking, no I/O.
namespace rig::haptic {

class ForceSource {
 public:
  virtual ~ForceSource() = default;
  virtual double force_N(double depth_mm, double front_mm, double velocity_mm_s) const noexcept = 0;
  virtual const char* describe() const noexcept = 0;
};

}  // namespace rig::haptic
