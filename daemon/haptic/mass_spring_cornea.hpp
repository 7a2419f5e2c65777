#pragma once
// The local corneal patch as a mass-spring mesh (paper Eq. 2, overdamped: the masses are
// small): c dr/dt + sum_j k_ij (|r_ij| - L_ij) r_ij/|r_ij| = F_i. An n x n grid in the
// corneal plane with stretching (neighbours), shearing (diagonals) and bending (two apart)
// springs: n = 13 gives the paper's 169 vertices and 886 springs. The rim is fixed. Until
// the puncture the vertices under the tip follow it; then the springs across the cut (as
// long as the blade is wide) are removed and the cut opens to the blade's thickness.
#include <vector>

namespace rig::haptic {

struct MeshSettings {
  int n = 13;             // vertices per side
  double patch_mm = 6.0;  // side of the square patch; spacing = patch / (n - 1)
  double k_stretch_N_per_mm = 1.0;
  double k_shear_N_per_mm = 0.5;
  double k_bend_N_per_mm = 0.2;
  double damping_Ns_per_mm = 0.05;  // c
  // The IOP keeps the cornea under tension: rest lengths are this fraction shorter than
  // the grid, which gives the membrane its stiffness against a push along the axis.
  double prestrain = 0.1;
  double blade_width_mm = 2.8;      // length of the cut
  double blade_thickness_mm = 0.2;  // how far the cut opens
  double tip_radius_mm = 0.3;       // vertices within this follow the tip
};

class MassSpringCornea {
 public:
  explicit MassSpringCornea(const MeshSettings& settings);  // allocates here, never in step()

  // One overdamped step [s] with the tip at depth [mm] below the surface.
  void step(double dt_s, double tip_depth_mm, bool punctured) noexcept;
  void reset() noexcept;

  int vertex_count() const { return static_cast<int>(x_.size()); }
  int spring_count() const { return static_cast<int>(springs_.size()); }
  int active_spring_count() const noexcept;
  // The row through the centre, across the cut: x [mm] and depth z [mm] (+ into the eye).
  int cross_section(double* x_mm, double* z_mm, int capacity) const noexcept;
  // Every vertex [mm], row-major; returns the count, or 0 (nothing written) above capacity.
  int positions(double* x_mm, double* y_mm, double* z_mm, int capacity) const noexcept;
  double depth_at_centre_mm() const noexcept;

 private:
  struct Spring {
    int i, j;
    double rest_mm, k_N_per_mm;
    bool crosses_cut;
  };
  void add_spring(int i, int j, double k);
  int index(int row, int column) const { return row * s_.n + column; }
  double spacing_mm() const { return s_.patch_mm / (s_.n - 1); }

  MeshSettings s_;
  std::vector<double> x_, y_, z_;     // positions [mm]
  std::vector<double> fx_, fy_, fz_;  // spring forces, reused every step
  std::vector<unsigned char> fixed_;  // rim
  std::vector<unsigned char> under_tip_;
  std::vector<Spring> springs_;
  bool cut_ = false;
};

}  // namespace rig::haptic
