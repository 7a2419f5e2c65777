#include "openhaptics_device.hpp"

#include <dlfcn.h>

#include <chrono>
#include <stdexcept>

namespace rig::drivers {

struct OpenHapticsDevice::Api {
  hd::HHD (*hdInitDevice)(hd::HDstring) = nullptr;
  void (*hdDisableDevice)(hd::HHD) = nullptr;
  hd::HHD (*hdGetCurrentDevice)() = nullptr;
  void (*hdEnable)(hd::HDenum) = nullptr;
  void (*hdDisable)(hd::HDenum) = nullptr;
  void (*hdBeginFrame)(hd::HHD) = nullptr;
  void (*hdEndFrame)(hd::HHD) = nullptr;
  void (*hdGetDoublev)(hd::HDenum, hd::HDdouble*) = nullptr;
  void (*hdSetDoublev)(hd::HDenum, const hd::HDdouble*) = nullptr;
  hd::HDErrorInfo (*hdGetError)() = nullptr;
  hd::HDSchedulerHandle (*hdScheduleAsynchronous)(hd::HDSchedulerCallback, void*,
                                                  hd::HDushort) = nullptr;
  void (*hdUnschedule)(hd::HDSchedulerHandle) = nullptr;
  void (*hdStartScheduler)() = nullptr;
  void (*hdStopScheduler)() = nullptr;
};

void OpenHapticsDevice::LibraryCloser::operator()(void* handle) const noexcept {
  dlclose(handle);
}

namespace {

template <typename F>
void resolve(void* library, const char* name, F& target) {
  void* symbol = dlsym(library, name);
  if (symbol == nullptr)
    throw std::runtime_error(std::string("OpenHaptics: symbol ") + name + " missing from libHD.so");
  target = reinterpret_cast<F>(symbol);
}

HapticFault fault_of(hd::HDerror code) {
  switch (code) {
    case hd::kWarmMotors:
      return HapticFault::kWarmMotors;
    case hd::kExceededMaxForce:
    case hd::kExceededMaxForceImpulse:
      return HapticFault::kExceededMaxForce;
    case hd::kExceededMaxVelocity:
      return HapticFault::kExceededMaxVelocity;
    case hd::kCommError:
    case hd::kCommConfigError:
      return HapticFault::kCommError;
    default:
      return HapticFault::kOther;
  }
}

}  // namespace

OpenHapticsDevice::OpenHapticsDevice(const std::string& library, const std::string& device_name)
    : api_(std::make_unique<Api>()) {
  library_.reset(dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL));
  if (!library_) {
    throw std::runtime_error("OpenHaptics library " + library + " not found (" + dlerror() +
                             "): install OpenHaptics for the Phantom, or use --device sim");
  }
  Api& a = *api_;
  resolve(library_.get(), "hdInitDevice", a.hdInitDevice);
  resolve(library_.get(), "hdDisableDevice", a.hdDisableDevice);
  resolve(library_.get(), "hdGetCurrentDevice", a.hdGetCurrentDevice);
  resolve(library_.get(), "hdEnable", a.hdEnable);
  resolve(library_.get(), "hdDisable", a.hdDisable);
  resolve(library_.get(), "hdBeginFrame", a.hdBeginFrame);
  resolve(library_.get(), "hdEndFrame", a.hdEndFrame);
  resolve(library_.get(), "hdGetDoublev", a.hdGetDoublev);
  resolve(library_.get(), "hdSetDoublev", a.hdSetDoublev);
  resolve(library_.get(), "hdGetError", a.hdGetError);
  resolve(library_.get(), "hdScheduleAsynchronous", a.hdScheduleAsynchronous);
  resolve(library_.get(), "hdUnschedule", a.hdUnschedule);
  resolve(library_.get(), "hdStartScheduler", a.hdStartScheduler);
  resolve(library_.get(), "hdStopScheduler", a.hdStopScheduler);
  device_ = a.hdInitDevice(device_name.empty() ? nullptr : device_name.c_str());
  const hd::HDErrorInfo error = a.hdGetError();
  if (device_ == hd::kInvalidHandle || error.errorCode != hd::kSuccess) {
    throw std::runtime_error("OpenHaptics: cannot initialise the device (HD error 0x" +
                             std::to_string(error.errorCode) + ")");
  }
  // Limits come from the device, never from a table of models.
  a.hdGetDoublev(hd::kNominalMaxForce, &limits_.max_force_N);
  a.hdGetDoublev(hd::kNominalMaxContinuousForce, &limits_.max_continuous_force_N);
  a.hdGetDoublev(hd::kNominalMaxStiffness, &limits_.max_stiffness_N_per_mm);
}

OpenHapticsDevice::~OpenHapticsDevice() {
  stop();
  if (device_ != hd::kInvalidHandle) api_->hdDisableDevice(device_);
}

std::string OpenHapticsDevice::describe() const {
  return "Phantom via OpenHaptics (libHD)";
}

void OpenHapticsDevice::start(HapticServo& servo) {
  servo_ = &servo;
  t0_s_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  running_.store(true);  // before the scheduler can call back
  api_->hdEnable(hd::kForceOutput);
  force_enabled_.store(true);
  callback_ = api_->hdScheduleAsynchronous(&OpenHapticsDevice::servo_callback, this,
                                           hd::kDefaultSchedulerPriority);
  api_->hdStartScheduler();
  if (check_error()) {
    running_.store(false);
    throw std::runtime_error("OpenHaptics: the servo scheduler did not start");
  }
}

void OpenHapticsDevice::stop() noexcept {
  if (!running_.exchange(false)) return;
  force_off();
  api_->hdStopScheduler();
  api_->hdUnschedule(callback_);
}

// Zero force from the next frame, and the amplifiers off now: the stall watchdog calls this from
// its own thread while the servo thread may be stalled (no frame to write zero force in; the
// device's own watchdog acts only after ~1 s, notes/probes.md). A stalled servo thread is in
// no HD call, so the state call does not race a frame.
void OpenHapticsDevice::force_off() noexcept {
  force_enabled_.store(false);
  api_->hdDisable(hd::kForceOutput);
}

bool OpenHapticsDevice::check_error() noexcept {
  const hd::HDErrorInfo error = api_->hdGetError();
  if (error.errorCode == hd::kSuccess) return false;
  force_enabled_.store(false);
  api_->hdDisable(hd::kForceOutput);
  if (servo_ != nullptr) servo_->device_fault(fault_of(error.errorCode));
  return true;
}

hd::HDCallbackCode OpenHapticsDevice::servo_callback(void* self) noexcept {
  return static_cast<OpenHapticsDevice*>(self)->tick();
}

hd::HDCallbackCode OpenHapticsDevice::tick() noexcept {
  api_->hdBeginFrame(api_->hdGetCurrentDevice());
  Vec3 position{};
  api_->hdGetDoublev(hd::kCurrentPosition, position.data());
  const double t =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count() -
      t0_s_;
  Vec3 force = servo_->tick(position, t);
  if (!force_enabled_.load(std::memory_order_relaxed)) force = {0.0, 0.0, 0.0};
  api_->hdSetDoublev(hd::kCurrentForce, force.data());
  api_->hdEndFrame(api_->hdGetCurrentDevice());
  ticks_.fetch_add(1, std::memory_order_relaxed);
  check_error();
  return running_.load(std::memory_order_relaxed) ? hd::kCallbackContinue : hd::kCallbackDone;
}

}  // namespace rig::drivers
