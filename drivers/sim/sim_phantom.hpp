#pragma once
// A simulated Phantom: 1 kHz servo on its own thread (or as fast as possible on a virtual
// clock), a virtual hand moving the end effector along the keratome axis, encoder
// quantisation (0.055 mm), one tick of force latency and a first-order force bandwidth.
// It records what the hand feels, for the haptic-vs-source error.
#include <atomic>
#include <thread>
#include <vector>

#include "rig/drivers/haptic_device.hpp"
#include "virtual_hand.hpp"

namespace rig::drivers {

struct SimPhantomSettings {
  double rate_hz = 1000.0;
  double encoder_resolution_mm = 0.055;
  double force_bandwidth_hz = 200.0;
  int latency_ticks = 1;
  HapticLimits limits{3.3, 0.88, 0.7};  // what an Omni reports (CHAI3D's table)
  Vec3 axis{0.0, 0.0, -1.0};            // keratome axis in device coordinates (into the eye)
  Vec3 surface_mm{0.0, 0.0, 0.0};       // device position of the corneal surface
  bool real_time = true;                // false: virtual clock, as fast as possible
  int priority = 80;
};

struct FeltSample {
  double t_s = 0.0;
  double depth_mm = 0.0;  // true tip depth
  double force_N = 0.0;   // felt force along the axis, + resisting insertion
};

class SimPhantom final : public HapticDevice {
 public:
  SimPhantom(const SimPhantomSettings& settings, const VirtualHand& hand);
  ~SimPhantom() override;
  std::string describe() const override { return "simulated Phantom"; }
  HapticLimits limits() const noexcept override { return s_.limits; }
  void start(HapticServo& servo) override;
  void stop() noexcept override;
  void force_off() noexcept override { forced_off_.store(true); }
  std::uint64_t ticks() const noexcept override { return ticks_.load(std::memory_order_relaxed); }
  bool running() const noexcept override { return running_.load(); }
  double output_latency_s() const noexcept override;
  double period_s() const noexcept override { return 1.0 / s_.rate_hz; }
  bool paced_by_wall_clock() const noexcept override { return s_.real_time; }

  void wait() noexcept;  // until the hand's trajectory is done
  bool forced_off() const noexcept { return forced_off_.load(); }
  const std::vector<FeltSample>& felt() const { return felt_; }  // after wait()/stop()

 private:
  void run() noexcept;
  void tick(std::size_t k) noexcept;

  SimPhantomSettings s_;
  const VirtualHand* hand_;
  HapticServo* servo_ = nullptr;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> forced_off_{false};
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> ticks_{0};
  std::vector<double> pending_;  // latency line of commanded forces [N]
  double output_N_ = 0.0;        // force after the bandwidth filter
  std::vector<FeltSample> felt_;
};

}  // namespace rig::drivers
