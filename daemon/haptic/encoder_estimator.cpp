#include "encoder_estimator.hpp"

#include <algorithm>
#include <cmath>

namespace rig::haptic {

EncoderEstimator::EncoderEstimator(double resolution_mm, double lead_s) noexcept
    : resolution_mm_(resolution_mm), lead_s_(lead_s) {}

void EncoderEstimator::reset() noexcept {
  started_ = false;
}

double EncoderEstimator::update(double raw_mm, double t_s) noexcept {
  if (!started_) {
    started_ = true;
    raw_mm_ = crossing_mm_ = previous_crossing_mm_ = estimate_mm_ = raw_mm;
    crossing_t_s_ = previous_crossing_t_s_ = t_s;
    cell_low_mm_ = raw_mm - resolution_mm_ / 2.0;
    cell_high_mm_ = raw_mm + resolution_mm_ / 2.0;
    velocity_mm_s_ = 0.0;
    direction_ = 0;
    return raw_mm;
  }
  const double step = raw_mm - raw_mm_;
  if (step != 0.0) {
    const int direction = step > 0.0 ? 1 : -1;
    const double half = std::min(std::abs(step), resolution_mm_) / 2.0;
    previous_crossing_mm_ = crossing_mm_;
    previous_crossing_t_s_ = crossing_t_s_;
    crossing_mm_ = std::abs(step) > 1.5 * resolution_mm_ ? raw_mm : raw_mm - direction * half;
    crossing_t_s_ = t_s;
    const double dt = crossing_t_s_ - previous_crossing_t_s_;
    velocity_mm_s_ =
        (direction == direction_ && dt > 0.0) ? (crossing_mm_ - previous_crossing_mm_) / dt : 0.0;
    direction_ = direction;
    raw_mm_ = raw_mm;
    cell_low_mm_ = raw_mm - half;
    cell_high_mm_ = raw_mm + half;
  } else if (velocity_mm_s_ != 0.0) {
    // No count yet: the hand is slower than the last crossings said (or stopped). Bound the
    // speed by what would have produced a count by now.
    const double since = t_s - crossing_t_s_;
    const double bound = resolution_mm_ / std::max(since, 1e-6);
    velocity_mm_s_ = std::copysign(std::min(std::abs(velocity_mm_s_), bound), velocity_mm_s_);
  }
  estimate_mm_ = std::clamp(crossing_mm_ + velocity_mm_s_ * (t_s - crossing_t_s_), cell_low_mm_,
                            cell_high_mm_);
  return estimate_mm_ + velocity_mm_s_ * lead_s_;
}

}  // namespace rig::haptic
