#include "virtual_hand.hpp"

#include <algorithm>

namespace rig::drivers {

PushingHand::PushingHand(double velocity_mm_s, double depth_mm, double start_mm, double hold_s)
    : v_(velocity_mm_s), depth_(depth_mm), start_(start_mm), hold_(hold_s) {}

double PushingHand::duration_s() const noexcept {
  return 2.0 * (depth_ - start_) / v_ + hold_;
}

double PushingHand::depth_mm(double t) const noexcept {
  const double in = (depth_ - start_) / v_;
  if (t <= in) return start_ + v_ * std::max(t, 0.0);
  if (t <= in + hold_) return depth_;
  return std::max(start_, depth_ - v_ * (t - in - hold_));
}

RecordedHand::RecordedHand(std::vector<double> t_s, std::vector<double> x_mm)
    : t_(std::move(t_s)), x_(std::move(x_mm)) {}

double RecordedHand::depth_mm(double t) const noexcept {
  if (t_.empty()) return 0.0;
  const auto it = std::lower_bound(t_.begin(), t_.end(), t);
  if (it == t_.begin()) return x_.front();
  if (it == t_.end()) return x_.back();
  const auto i = static_cast<std::size_t>(it - t_.begin());
  const double w = (t - t_[i - 1]) / std::max(t_[i] - t_[i - 1], 1e-12);
  return x_[i - 1] + w * (x_[i] - x_[i - 1]);
}

}  // namespace rig::drivers
