#pragma once
// Position between encoder counts. The Phantom reports its tip position quantised (about
// 0.055 mm on an Omni); at 2 mm/s that is a new count every 27 ms, and where the rendered
// force is steep (the puncture drop, about 0.8 N/mm) rendering the raw count would be off
// by up to 20 mN. Each count change marks the moment the true position crossed the midpoint
// between the two counts; from the last two crossings we know the velocity and extrapolate,
// never leaving the cell of the current count (the estimate is never worse than the raw
// count). A reversal resets the velocity to zero. Steps larger than 1.5 counts (fast hand)
// are taken as they come. Then the estimate is predicted ahead by the device's output
// latency, so the force lands when the hand is where it was computed for.
namespace rig::haptic {

class EncoderEstimator {
 public:
  // resolution [mm]: one count; lead [s]: how far ahead to predict.
  EncoderEstimator(double resolution_mm, double lead_s) noexcept;
  void reset() noexcept;
  // raw [mm] as read this tick, at t [s]. Returns the predicted position [mm].
  double update(double raw_mm, double t_s) noexcept;
  double velocity_mm_s() const noexcept { return velocity_mm_s_; }
  double estimate_mm() const noexcept { return estimate_mm_; }

 private:
  double resolution_mm_, lead_s_;
  bool started_ = false;
  double raw_mm_ = 0.0;        // current count [mm]
  double crossing_mm_ = 0.0;   // where the last change crossed [mm]
  double crossing_t_s_ = 0.0;  // when [s]
  double previous_crossing_mm_ = 0.0, previous_crossing_t_s_ = 0.0;
  int direction_ = 0;                              // of the last change: +1, -1
  double cell_low_mm_ = 0.0, cell_high_mm_ = 0.0;  // where the true position can be
  double velocity_mm_s_ = 0.0;
  double estimate_mm_ = 0.0;
};

}  // namespace rig::haptic
