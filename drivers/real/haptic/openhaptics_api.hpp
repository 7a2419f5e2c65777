#pragma once
// The part of OpenHaptics' HD API rigd uses, declared here so the product builds and runs
// without OpenHaptics; libHD.so is loaded at run time (as CHAI3D does). Values from
// SensAble's hdDefines.h / hdScheduler.h (OpenHaptics 3.0).
#include <cstdint>

namespace rig::drivers::hd {

using HHD = unsigned int;
using HDenum = unsigned int;
using HDerror = unsigned int;
using HDushort = unsigned short;
using HDdouble = double;
using HDstring = const char*;
using HDCallbackCode = unsigned int;
using HDSchedulerHandle = unsigned long;
using HDSchedulerCallback = HDCallbackCode (*)(void* user_data);

struct HDErrorInfo {
  HDerror errorCode;
  int internalErrorCode;
  HHD hHD;
};

inline constexpr HHD kInvalidHandle = 0xFFFFFFFF;
inline constexpr HDCallbackCode kCallbackDone = 0;
inline constexpr HDCallbackCode kCallbackContinue = 1;
inline constexpr HDushort kDefaultSchedulerPriority = (0xFFFF + 0) / 2;

inline constexpr HDerror kSuccess = 0x0000;
inline constexpr HDerror kWarmMotors = 0x0200;
inline constexpr HDerror kExceededMaxForce = 0x0201;
inline constexpr HDerror kExceededMaxForceImpulse = 0x0202;
inline constexpr HDerror kExceededMaxVelocity = 0x0203;
inline constexpr HDerror kForceError = 0x0204;
inline constexpr HDerror kDeviceFault = 0x0300;
inline constexpr HDerror kCommError = 0x0302;
inline constexpr HDerror kCommConfigError = 0x0303;

inline constexpr HDenum kCurrentPosition = 0x2050;
inline constexpr HDenum kNominalMaxStiffness = 0x2602;
inline constexpr HDenum kNominalMaxForce = 0x2603;
inline constexpr HDenum kNominalMaxContinuousForce = 0x2604;
inline constexpr HDenum kCurrentForce = 0x2700;
inline constexpr HDenum kForceOutput = 0x4000;

}  // namespace rig::drivers::hd
