#include "cpu_wake_latency_request.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

namespace rig::drivers {

CpuWakeLatencyRequest::CpuWakeLatencyRequest(int max_us) {
  if (max_us < 0) {
    why_not_ = "not requested";
    return;
  }
  fd_ = ::open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
  if (fd_ < 0) {
    why_not_ = std::string("/dev/cpu_dma_latency: ") + std::strerror(errno);
    return;
  }
  // The kernel keeps the request while the file stays open (a binary s32, in microseconds).
  const std::int32_t value = max_us;
  if (::write(fd_, &value, sizeof value) != static_cast<ssize_t>(sizeof value)) {
    why_not_ = std::string("/dev/cpu_dma_latency: ") + std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
  }
}

CpuWakeLatencyRequest::~CpuWakeLatencyRequest() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace rig::drivers
