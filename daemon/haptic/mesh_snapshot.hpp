#pragma once
// What the servo publishes for the page (through a triple buffer, at 50 Hz): the mesh's
// cross-section through the cut and the state of the rendering.
#include <cstdint>

namespace rig::haptic {

struct MeshSnapshot {
  static constexpr int kMaxPoints = 256;
  std::uint64_t sequence = 0;   // 0: nothing published yet
  double t_s = 0.0;
  double tip_depth_mm = 0.0;
  double force_N = 0.0;
  bool punctured = false;
  int point_count = 0;
  double x_mm[kMaxPoints]{};
  double z_mm[kMaxPoints]{};
};

}  // namespace rig::haptic
