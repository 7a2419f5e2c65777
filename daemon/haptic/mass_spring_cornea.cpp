#include "mass_spring_cornea.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rig::haptic {

MassSpringCornea::MassSpringCornea(const MeshSettings& settings) : s_(settings) {
  if (s_.n < 3) throw std::invalid_argument("mesh: n must be at least 3");
  if (!(s_.prestrain >= 0.0 && s_.prestrain < 0.5))
    throw std::invalid_argument("mesh: prestrain must be in [0, 0.5)");
  const int n = s_.n;
  const auto count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  x_.resize(count), y_.resize(count), z_.resize(count);
  fx_.resize(count), fy_.resize(count), fz_.resize(count);
  fixed_.resize(count), under_tip_.resize(count);
  reset();
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      if (c + 1 < n) add_spring(index(r, c), index(r, c + 1), s_.k_stretch_N_per_mm);
      if (r + 1 < n) add_spring(index(r, c), index(r + 1, c), s_.k_stretch_N_per_mm);
      if (r + 1 < n && c + 1 < n) add_spring(index(r, c), index(r + 1, c + 1), s_.k_shear_N_per_mm);
      if (r + 1 < n && c > 0) add_spring(index(r, c), index(r + 1, c - 1), s_.k_shear_N_per_mm);
      if (c + 2 < n) add_spring(index(r, c), index(r, c + 2), s_.k_bend_N_per_mm);
      if (r + 2 < n) add_spring(index(r, c), index(r + 2, c), s_.k_bend_N_per_mm);
    }
  }
}

void MassSpringCornea::reset() noexcept {
  const int n = s_.n;
  const double half = (n - 1) * spacing_mm() / 2.0;
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const auto i = static_cast<std::size_t>(index(r, c));
      x_[i] = c * spacing_mm() - half;
      y_[i] = r * spacing_mm() - half;
      z_[i] = 0.0;
      fixed_[i] = (r == 0 || c == 0 || r == n - 1 || c == n - 1) ? 1 : 0;
      under_tip_[i] = std::hypot(x_[i], y_[i]) <= s_.tip_radius_mm ? 1 : 0;
    }
  }
  cut_ = false;
}

void MassSpringCornea::add_spring(int i, int j, double k) {
  const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
  const double rest = (1.0 - s_.prestrain) * std::hypot(x_[b] - x_[a], y_[b] - y_[a]);
  // The cut runs along y through the centre, just right of the centre column.
  const double cut_x = 0.25 * spacing_mm();
  const bool across = (x_[a] - cut_x) * (x_[b] - cut_x) < 0.0 &&
                      std::max(std::abs(y_[a]), std::abs(y_[b])) <= s_.blade_width_mm / 2.0;
  springs_.push_back({i, j, rest, k, across});
}

int MassSpringCornea::active_spring_count() const noexcept {
  int n = 0;
  for (const Spring& s : springs_) n += (cut_ && s.crosses_cut) ? 0 : 1;
  return n;
}

void MassSpringCornea::step(double dt_s, double tip_depth_mm, bool punctured) noexcept {
  cut_ = cut_ || punctured;
  std::fill(fx_.begin(), fx_.end(), 0.0);
  std::fill(fy_.begin(), fy_.end(), 0.0);
  std::fill(fz_.begin(), fz_.end(), 0.0);
  for (const Spring& s : springs_) {
    if (cut_ && s.crosses_cut) continue;
    const auto a = static_cast<std::size_t>(s.i), b = static_cast<std::size_t>(s.j);
    const double dx = x_[b] - x_[a], dy = y_[b] - y_[a], dz = z_[b] - z_[a];
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (length < 1e-12) continue;
    const double f = s.k_N_per_mm * (length - s.rest_mm) / length;  // tension pulls a towards b
    fx_[a] += f * dx, fy_[a] += f * dy, fz_[a] += f * dz;
    fx_[b] -= f * dx, fy_[b] -= f * dy, fz_[b] -= f * dz;
  }
  const double mobility = dt_s / s_.damping_Ns_per_mm;  // overdamped: dr = F dt / c
  const double open = s_.blade_thickness_mm / 2.0;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    if (fixed_[i] != 0) continue;
    x_[i] += mobility * fx_[i];
    y_[i] += mobility * fy_[i];
    z_[i] += mobility * fz_[i];
    if (!cut_ && under_tip_[i] != 0) z_[i] = std::max(0.0, tip_depth_mm);  // follows the tip
    if (cut_ && tip_depth_mm > 0.0 && std::abs(y_[i]) <= s_.blade_width_mm / 2.0) {
      // The blade holds the cut open to its thickness.
      if (x_[i] < 0.25 * spacing_mm() && x_[i] > -open) x_[i] = -open;
      if (x_[i] >= 0.25 * spacing_mm() && x_[i] < open + 0.25 * spacing_mm())
        x_[i] = open + 0.25 * spacing_mm();
    }
  }
}

int MassSpringCornea::cross_section(double* x_mm, double* z_mm, int capacity) const noexcept {
  const int row = s_.n / 2;
  const int count = std::min(capacity, s_.n);
  for (int c = 0; c < count; ++c) {
    const auto i = static_cast<std::size_t>(index(row, c));
    x_mm[c] = x_[i];
    z_mm[c] = z_[i];
  }
  return count;
}

int MassSpringCornea::positions(double* x_mm, double* y_mm, double* z_mm,
                                int capacity) const noexcept {
  const int count = vertex_count();
  if (count > capacity) return 0;
  std::copy(x_.begin(), x_.end(), x_mm);
  std::copy(y_.begin(), y_.end(), y_mm);
  std::copy(z_.begin(), z_.end(), z_mm);
  return count;
}

double MassSpringCornea::depth_at_centre_mm() const noexcept {
  return z_[static_cast<std::size_t>(index(s_.n / 2, s_.n / 2))];
}

}  // namespace rig::haptic
