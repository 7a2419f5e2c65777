#pragma once
// What the servo publishes for the page (through a triple buffer, at 50 Hz): the mesh's
// cross-section through the cut, every vertex of a mesh up to kMaxGridVertices (the page's
// 3D view; a finer mesh publishes its cross-section only) and the state of the rendering.
#include <cstdint>

namespace rig::haptic {

struct MeshSnapshot {
  static constexpr int kMaxPoints = 256;
  std::uint64_t sequence = 0;  // 0: nothing published yet
  double t_s = 0.0;
  double tip_depth_mm = 0.0;
  double force_N = 0.0;
  bool punctured = false;
  int point_count = 0;
  double x_mm[kMaxPoints]{};
  double z_mm[kMaxPoints]{};
  static constexpr int kMaxGridVertices = 1024;  // 32 x 32; the default mesh has 169
  int grid_count = 0;                            // 0: mesh too fine, not published whole
  double grid_x_mm[kMaxGridVertices]{};          // row-major, as MassSpringCornea numbers them
  double grid_y_mm[kMaxGridVertices]{};
  double grid_z_mm[kMaxGridVertices]{};  // depth, + into the eye
};

}  // namespace rig::haptic
