#pragma once
// Phantom (Omni, Touch) through OpenHaptics' HD API, loaded with dlopen("libHD.so") at run
// time. The servo runs in OpenHaptics' scheduler callback (hdScheduleAsynchronous): begin
// frame, read HD_CURRENT_POSITION, set HD_CURRENT_FORCE, end frame; any hdGetError() turns
// force output off and reports the fault (warm motors, max force, comm errors).
#include <atomic>
#include <memory>
#include <string>

#include "openhaptics_api.hpp"
#include "rig/drivers/haptic_device.hpp"

namespace rig::drivers {

class OpenHapticsDevice final : public HapticDevice {
 public:
  // Loads the library and initialises the device; throws std::runtime_error naming what is
  // missing (the library, a symbol, or the device).
  explicit OpenHapticsDevice(const std::string& library = "libHD.so",
                             const std::string& device_name = "");
  ~OpenHapticsDevice() override;
  std::string describe() const override;
  HapticLimits limits() const noexcept override { return limits_; }
  void start(HapticServo& servo) override;
  void stop() noexcept override;
  void force_off() noexcept override;
  std::uint64_t ticks() const noexcept override { return ticks_.load(std::memory_order_relaxed); }
  bool running() const noexcept override { return running_.load(); }
  // The force set in a frame is sent at hdEndFrame and applied by the amplifiers within the
  // next servo tick.
  double output_latency_s() const noexcept override { return 0.001; }
  double period_s() const noexcept override { return 0.001; }
  bool paced_by_wall_clock() const noexcept override {
    return true;
  }  // a Phantom always has a hand on it

 private:
  struct Api;
  static hd::HDCallbackCode servo_callback(void* self) noexcept;
  hd::HDCallbackCode tick() noexcept;
  bool check_error() noexcept;

  struct LibraryCloser {
    void operator()(void* handle) const noexcept;
  };
  std::unique_ptr<void, LibraryCloser> library_;
  std::unique_ptr<Api> api_;
  hd::HHD device_ = hd::kInvalidHandle;
  hd::HDSchedulerHandle callback_ = 0;
  HapticServo* servo_ = nullptr;
  HapticLimits limits_{};
  std::atomic<bool> force_enabled_{false};
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> ticks_{0};
  double t0_s_ = 0.0;
};

}  // namespace rig::drivers
