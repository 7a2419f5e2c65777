// A stand-in for OpenHaptics' libHD.so with the same C ABI, for testing the dlopen path
// without a Phantom: a device whose stylus moves along -z at 2 mm/s from 3 mm outside the
// surface, a scheduler thread calling the servo callbacks at 1 kHz, and hooks (fake_hd_*)
// for a test to inject an error and read the last force set.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "haptic/openhaptics_api.hpp"

namespace hd = rig::drivers::hd;

namespace {

struct Scheduled {
  hd::HDSchedulerCallback callback;
  void* user_data;
  hd::HDSchedulerHandle handle;
  bool active;
};

std::mutex g_mutex;
std::vector<Scheduled> g_callbacks;
std::thread g_scheduler;
std::atomic<bool> g_running{false};
std::atomic<bool> g_force_output{false};
std::atomic<hd::HDerror> g_pending_error{hd::kSuccess};
std::atomic<hd::HDerror> g_init_error{hd::kSuccess};
std::atomic<double> g_last_force_z{0.0};
std::atomic<long> g_frames{0};
std::atomic<long> g_stall_ms{
    0};  // the scheduler's next frame comes this much later [ms] (a stalled servo thread)
// The frames whose stylus was within 0.1 mm of 1 mm below the surface: the force [N] set
// along z and the true depth [mm], summed (a mean over ~100 frames, so one frame disturbed by
// a loaded machine does not decide the test).
std::mutex g_band_mutex;
double g_band_force_sum = 0.0, g_band_depth_sum = 0.0;
long g_band_frames = 0;
std::atomic<double> g_frame_z_mm{3.0};  // [mm] true stylus z when the servo read it this frame
constexpr double kCount_mm = 0.055;     // one encoder count at the tip, as on an Omni
std::atomic<long> g_start_ns{0};        // the stylus starts moving at the first frame (0: not yet)
hd::HDSchedulerHandle g_next_handle = 1;

long now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double stylus_z_mm() {
  if (g_start_ns.load() == 0) return 3.0;
  const long now = now_ns();
  const double t = static_cast<double>(now - g_start_ns.load()) * 1e-9;
  return 3.0 - 2.0 * t;  // surface at z = 0 is reached after 1.5 s
}

void scheduler_loop() {
  auto next = std::chrono::steady_clock::now();
  while (g_running.load()) {
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
    if (const long stall_ms = g_stall_ms.exchange(0); stall_ms > 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(stall_ms));
      next = std::chrono::steady_clock::now();
    }
    std::lock_guard lock(g_mutex);
    for (Scheduled& s : g_callbacks) {
      if (s.active && s.callback(s.user_data) == hd::kCallbackDone) s.active = false;
    }
  }
}

}  // namespace

extern "C" {

hd::HHD hdInitDevice(hd::HDstring /*name*/) {
  return g_init_error.load() == hd::kSuccess ? 1U : hd::kInvalidHandle;
}
void hdDisableDevice(hd::HHD /*device*/) {}
hd::HHD hdGetCurrentDevice() {
  return 1U;
}
void hdEnable(hd::HDenum cap) {
  if (cap == hd::kForceOutput) g_force_output.store(true);
}
void hdDisable(hd::HDenum cap) {
  if (cap == hd::kForceOutput) g_force_output.store(false);
}
// The stylus starts at the servo's first frame, as the servo's ramp-in does: a session that
// starts late on a loaded machine still meets the surface after its ramp-in is over.
void hdBeginFrame(hd::HHD /*device*/) {
  long unset = 0;
  g_start_ns.compare_exchange_strong(unset, now_ns());
}
void hdEndFrame(hd::HHD /*device*/) {
  g_frames.fetch_add(1);
}

void hdGetDoublev(hd::HDenum what, hd::HDdouble* value) {
  switch (what) {
    case hd::kCurrentPosition:
      g_frame_z_mm.store(stylus_z_mm());
      value[0] = 0.0, value[1] = 0.0,
      value[2] = std::round(g_frame_z_mm.load() / kCount_mm) * kCount_mm;
      break;
    case hd::kNominalMaxForce:
      value[0] = 3.3;
      break;
    case hd::kNominalMaxContinuousForce:
      value[0] = 0.6;
      break;  // differs from the sim's 0.88 on purpose
    case hd::kNominalMaxStiffness:
      value[0] = 0.9;
      break;
    default:
      value[0] = 0.0;
  }
}

void hdSetDoublev(hd::HDenum what, const hd::HDdouble* value) {
  if (what != hd::kCurrentForce) return;
  const double force_z = g_force_output.load() ? value[2] : 0.0;
  g_last_force_z.store(force_z);
  // Judged at the position the servo read in this frame (not at the time of the write, which a
  // descheduled servo thread makes later).
  const double depth_mm = -g_frame_z_mm.load();
  if (std::abs(depth_mm - 1.0) <= 0.1) {
    std::lock_guard lock(g_band_mutex);
    g_band_force_sum += force_z;
    g_band_depth_sum += depth_mm;
    ++g_band_frames;
  }
}

hd::HDErrorInfo hdGetError() {
  hd::HDErrorInfo info{g_pending_error.exchange(hd::kSuccess), 0, 1U};
  if (info.errorCode == hd::kSuccess) info.errorCode = g_init_error.exchange(hd::kSuccess);
  return info;
}

hd::HDSchedulerHandle hdScheduleAsynchronous(hd::HDSchedulerCallback callback, void* user_data,
                                             hd::HDushort /*priority*/) {
  std::lock_guard lock(g_mutex);
  g_callbacks.push_back({callback, user_data, g_next_handle, true});
  return g_next_handle++;
}

void hdUnschedule(hd::HDSchedulerHandle handle) {
  std::lock_guard lock(g_mutex);
  for (Scheduled& s : g_callbacks) {
    if (s.handle == handle) s.active = false;
  }
}

void hdStartScheduler() {
  g_start_ns.store(0);
  g_running.store(true);
  g_scheduler = std::thread(scheduler_loop);
}

void hdStopScheduler() {
  g_running.store(false);
  if (g_scheduler.joinable()) g_scheduler.join();
}

// Test hooks.
void fake_hd_inject_error(hd::HDerror code) {
  g_pending_error.store(code);
}
void fake_hd_fail_init(hd::HDerror code) {
  g_init_error.store(code);
}
void fake_hd_stall_scheduler(long ms) {
  g_stall_ms.store(ms);
}
double fake_hd_last_force_z() {
  return g_last_force_z.load();
}
int fake_hd_force_output_enabled() {
  return g_force_output.load() ? 1 : 0;
}
long fake_hd_frames() {
  return g_frames.load();
}
// Means over the frames 0.9-1.1 mm deep: force [N], depth [mm]; and how many frames.
double fake_hd_force_at_1mm() {
  std::lock_guard lock(g_band_mutex);
  return g_band_frames > 0 ? g_band_force_sum / static_cast<double>(g_band_frames) : 0.0;
}
double fake_hd_depth_at_1mm() {
  std::lock_guard lock(g_band_mutex);
  return g_band_frames > 0 ? g_band_depth_sum / static_cast<double>(g_band_frames) : 0.0;
}
long fake_hd_frames_at_1mm() {
  std::lock_guard lock(g_band_mutex);
  return g_band_frames;
}

}  // extern "C"
