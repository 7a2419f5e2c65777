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
// The force [N] set along z in the frame where the stylus was closest to 1 mm below the surface.
std::atomic<double> g_force_at_1mm{0.0};
std::atomic<double> g_best_distance_to_1mm{1e9};
std::atomic<long> g_start_ns{0};
hd::HDSchedulerHandle g_next_handle = 1;

double stylus_z_mm() {
  const long now = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
  const double t = static_cast<double>(now - g_start_ns.load()) * 1e-9;
  return 3.0 - 2.0 * t;  // surface at z = 0 is reached after 1.5 s
}

void scheduler_loop() {
  auto next = std::chrono::steady_clock::now();
  while (g_running.load()) {
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
    std::lock_guard lock(g_mutex);
    for (Scheduled& s : g_callbacks) {
      if (s.active && s.callback(s.user_data) == hd::kCallbackDone) s.active = false;
    }
  }
}

}  // namespace

extern "C" {

hd::HHD hdInitDevice(hd::HDstring /*name*/) { return g_init_error.load() == hd::kSuccess ? 1U : hd::kInvalidHandle; }
void hdDisableDevice(hd::HHD /*device*/) {}
hd::HHD hdGetCurrentDevice() { return 1U; }
void hdEnable(hd::HDenum cap) {
  if (cap == hd::kForceOutput) g_force_output.store(true);
}
void hdDisable(hd::HDenum cap) {
  if (cap == hd::kForceOutput) g_force_output.store(false);
}
void hdBeginFrame(hd::HHD /*device*/) {}
void hdEndFrame(hd::HHD /*device*/) { g_frames.fetch_add(1); }

void hdGetDoublev(hd::HDenum what, hd::HDdouble* value) {
  switch (what) {
    case hd::kCurrentPosition: value[0] = 0.0, value[1] = 0.0, value[2] = stylus_z_mm(); break;
    case hd::kNominalMaxForce: value[0] = 3.3; break;
    case hd::kNominalMaxContinuousForce: value[0] = 0.6; break;  // differs from the sim's 0.88 on purpose
    case hd::kNominalMaxStiffness: value[0] = 0.9; break;
    default: value[0] = 0.0;
  }
}

void hdSetDoublev(hd::HDenum what, const hd::HDdouble* value) {
  if (what != hd::kCurrentForce) return;
  const double force_z = g_force_output.load() ? value[2] : 0.0;
  g_last_force_z.store(force_z);
  const double distance = std::abs(-stylus_z_mm() - 1.0);
  if (distance < g_best_distance_to_1mm.load()) {
    g_best_distance_to_1mm.store(distance);
    g_force_at_1mm.store(force_z);
  }
}

hd::HDErrorInfo hdGetError() {
  hd::HDErrorInfo info{g_pending_error.exchange(hd::kSuccess), 0, 1U};
  if (info.errorCode == hd::kSuccess) info.errorCode = g_init_error.exchange(hd::kSuccess);
  return info;
}

hd::HDSchedulerHandle hdScheduleAsynchronous(hd::HDSchedulerCallback callback, void* user_data, hd::HDushort /*priority*/) {
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
  g_start_ns.store(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count());
  g_running.store(true);
  g_scheduler = std::thread(scheduler_loop);
}

void hdStopScheduler() {
  g_running.store(false);
  if (g_scheduler.joinable()) g_scheduler.join();
}

// Test hooks.
void fake_hd_inject_error(hd::HDerror code) { g_pending_error.store(code); }
void fake_hd_fail_init(hd::HDerror code) { g_init_error.store(code); }
double fake_hd_last_force_z() { return g_last_force_z.load(); }
int fake_hd_force_output_enabled() { return g_force_output.load() ? 1 : 0; }
long fake_hd_frames() { return g_frames.load(); }
double fake_hd_force_at_1mm() { return g_force_at_1mm.load(); }

}  // extern "C"
