#pragma once
// How the servo renders: geometry of the virtual keratome, safety limits and the mesh.
#include <optional>

#include "mass_spring_cornea.hpp"
#include "rig/drivers/haptic_device.hpp"

namespace rig::haptic {

struct ServoSettings {
  drivers::Vec3 axis{0.0, 0.0, -1.0};  // keratome axis in device coordinates, into the eye (unit)
  // Device position of the corneal surface [mm]; unset: `approach_mm` ahead of where the
  // stylus is at the first tick.
  std::optional<drivers::Vec3> surface_mm;
  double approach_mm = 5.0;
  double period_s = 0.001;                // the device's servo period [s]
  double output_latency_s = 0.001;        // the device's command-to-hand lag [s], predicted over
  double position_resolution_mm = 0.055;  // one encoder count at the tip
  bool estimate_between_counts = true;    // false: render the raw counts (for comparison only)
  double ramp_in_s = 0.5;                 // force scales 0 -> 1 over this from the first tick
  double max_slew_N_per_s = 50.0;         // largest force change the servo commands
  double guide_stiffness_N_per_mm = 0.3;  // holds the blade on its axis while in tissue
  bool count_late_ticks = true;           // false on a virtual clock (wall gaps mean nothing)
  bool mesh_enabled = true;
  int mesh_publish_every_ticks = 20;  // 50 Hz at 1 kHz
  MeshSettings mesh;
};

}  // namespace rig::haptic
