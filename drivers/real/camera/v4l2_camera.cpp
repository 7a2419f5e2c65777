#include "v4l2_camera.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "clock/monotonic_clock.hpp"

namespace rig::drivers {
namespace {

// The one place where errno becomes a cyclic status.
IoStatus status_from_errno(int error_number) noexcept {
  switch (error_number) {
    case EAGAIN:
    case EINTR:
      return IoStatus::kTimeout;
    case ENODEV:
    case ENXIO:
    case EIO:
    case EPIPE:
      return IoStatus::kLinkDown;  // unplugged, broken stream
    case EINVAL:
      return IoStatus::kNotReady;
    default:
      return IoStatus::kBadData;
  }
}

int xioctl(int fd, unsigned long request, void* argument) noexcept {
  int r = 0;
  do r = ::ioctl(fd, request, argument);
  while (r < 0 && errno == EINTR);
  return r;
}

std::uint32_t fourcc_of(PixelFormat format) noexcept {
  switch (format) {
    case PixelFormat::kMono8:
      return V4L2_PIX_FMT_GREY;
    case PixelFormat::kRgb8:
      return V4L2_PIX_FMT_RGB24;
    case PixelFormat::kYuyv:
      return V4L2_PIX_FMT_YUYV;
  }
  return V4L2_PIX_FMT_GREY;
}

bool format_of(std::uint32_t fourcc, PixelFormat& format) noexcept {
  if (fourcc == V4L2_PIX_FMT_GREY)
    format = PixelFormat::kMono8;
  else if (fourcc == V4L2_PIX_FMT_RGB24)
    format = PixelFormat::kRgb8;
  else if (fourcc == V4L2_PIX_FMT_YUYV)
    format = PixelFormat::kYuyv;
  else
    return false;
  return true;
}

std::string fourcc_text(std::uint32_t fourcc) {
  return {static_cast<char>(fourcc & 0xff), static_cast<char>((fourcc >> 8) & 0xff),
          static_cast<char>((fourcc >> 16) & 0xff), static_cast<char>((fourcc >> 24) & 0xff)};
}

}  // namespace

V4l2Camera::V4l2Camera(const std::string& device, const CameraSettings& settings)
    : device_(device) {
  fd_ = ::open(device.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0)
    throw std::runtime_error("V4L2 camera " + device + ": cannot open (" + std::strerror(errno) +
                             ")");
  try {
    v4l2_capability cap{};
    if (xioctl(fd_, VIDIOC_QUERYCAP, &cap) < 0)
      throw std::runtime_error("V4L2 camera " + device + ": not a V4L2 device (" +
                               std::strerror(errno) + ")");
    const std::uint32_t caps =
        (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
    if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 || (caps & V4L2_CAP_STREAMING) == 0)
      throw std::runtime_error("V4L2 camera " + device + ": no video capture with streaming I/O");
    negotiate_format(settings);
    set_frame_rate(settings.frame_rate_hz);
    map_buffers(settings.buffer_count);
    description_ = "V4L2 " + device + " (" + reinterpret_cast<const char*>(cap.card) + ") " +
                   std::to_string(width_) + "x" + std::to_string(height_) + " " +
                   fourcc_text(fourcc_of(format_)) + " @ " + std::to_string(frame_rate_hz_) + " Hz";
  } catch (...) {
    unmap_buffers();
    ::close(fd_);
    throw;
  }
}

V4l2Camera::~V4l2Camera() {
  stop();
  unmap_buffers();
  ::close(fd_);
}

void V4l2Camera::negotiate_format(const CameraSettings& settings) {
  // The requested format first, then the others rigd can store, in that order.
  const PixelFormat order[] = {settings.pixel_format, PixelFormat::kMono8, PixelFormat::kYuyv,
                               PixelFormat::kRgb8};
  std::string offered;
  for (const PixelFormat wanted : order) {
    v4l2_format fmt{};
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    fmt.fmt.pix.width = static_cast<std::uint32_t>(settings.width);
    fmt.fmt.pix.height = static_cast<std::uint32_t>(settings.height);
    fmt.fmt.pix.pixelformat = fourcc_of(wanted);
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (xioctl(fd_, VIDIOC_S_FMT, &fmt) < 0)
      throw std::runtime_error("V4L2 camera " + device_ + ": VIDIOC_S_FMT failed (" +
                               std::strerror(errno) +
                               (errno == EBUSY ? "; in use by another program" : "") + ")");
    PixelFormat got{};
    if (format_of(fmt.fmt.pix.pixelformat, got) && fmt.fmt.pix.field == V4L2_FIELD_NONE) {
      format_ = got;
      width_ = static_cast<int>(fmt.fmt.pix.width);
      height_ = static_cast<int>(fmt.fmt.pix.height);
      return;
    }
    offered += " " + fourcc_text(fmt.fmt.pix.pixelformat);
  }
  throw std::runtime_error("V4L2 camera " + device_ +
                           ": offers none of GREY, YUYV, RGB3 progressive (offered" + offered +
                           ")");
}

void V4l2Camera::set_frame_rate(double hz) {
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_G_PARM, &parm) == 0 &&
      (parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) != 0 && hz > 0) {
    parm.parm.capture.timeperframe =
        v4l2_fract{1000, static_cast<std::uint32_t>(std::lround(hz * 1000.0))};
    if (xioctl(fd_, VIDIOC_S_PARM, &parm) < 0)
      throw std::runtime_error("V4L2 camera " + device_ + ": frame rate " + std::to_string(hz) +
                               " Hz refused (" + std::strerror(errno) + ")");
  }
  const v4l2_fract t = parm.parm.capture.timeperframe;
  frame_rate_hz_ = t.numerator > 0 ? static_cast<double>(t.denominator) / t.numerator : 0.0;
}

void V4l2Camera::map_buffers(int count) {
  v4l2_requestbuffers req{};
  req.count = static_cast<std::uint32_t>(count);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_REQBUFS, &req) < 0 || req.count < 2)
    throw std::runtime_error("V4L2 camera " + device_ + ": no memory-mapped buffers (" +
                             std::strerror(errno) + ")");
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(fd_, VIDIOC_QUERYBUF, &buf) < 0)
      throw std::runtime_error("V4L2 camera " + device_ + ": VIDIOC_QUERYBUF failed");
    void* address =
        ::mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buf.m.offset);
    if (address == MAP_FAILED)
      throw std::runtime_error("V4L2 camera " + device_ + ": mmap failed (" + std::strerror(errno) +
                               ")");
    buffers_.push_back(Mapping{address, buf.length});
    monotonic_timestamps_ =
        (buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
  }
}

void V4l2Camera::unmap_buffers() noexcept {
  for (const Mapping& m : buffers_) ::munmap(m.address, m.length);
  buffers_.clear();
}

IoStatus V4l2Camera::start() noexcept {
  if (streaming_) return IoStatus::kOk;
  for (std::size_t i = 0; i < buffers_.size(); ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = static_cast<std::uint32_t>(i);
    if (xioctl(fd_, VIDIOC_QBUF, &buf) < 0) return status_from_errno(errno);
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) < 0) return status_from_errno(errno);
  streaming_ = true;
  lent_ = -1;
  last_sequence_ = -1;
  return IoStatus::kOk;
}

IoStatus V4l2Camera::stop() noexcept {
  if (!streaming_) return IoStatus::kOk;
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  streaming_ = false;
  lent_ = -1;  // STREAMOFF returns every buffer to the driver
  return xioctl(fd_, VIDIOC_STREAMOFF, &type) < 0 ? status_from_errno(errno) : IoStatus::kOk;
}

IoStatus V4l2Camera::requeue_lent() noexcept {
  if (lent_ < 0) return IoStatus::kOk;
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  buf.index = static_cast<std::uint32_t>(lent_);
  lent_ = -1;
  return xioctl(fd_, VIDIOC_QBUF, &buf) < 0 ? status_from_errno(errno) : IoStatus::kOk;
}

IoStatus V4l2Camera::next_frame(FrameView& frame, int timeout_us) noexcept {
  if (!streaming_) return IoStatus::kNotReady;
  if (const IoStatus s = requeue_lent(); s != IoStatus::kOk) return s;
  pollfd pfd{fd_, POLLIN, 0};
  const int ready = ::poll(&pfd, 1, (timeout_us + 999) / 1000);
  if (ready == 0) return IoStatus::kTimeout;
  if (ready < 0) return status_from_errno(errno);
  if ((pfd.revents & (POLLERR | POLLHUP)) != 0) return IoStatus::kLinkDown;
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &buf) < 0) return status_from_errno(errno);
  lent_ = static_cast<int>(buf.index);
  const std::int64_t sequence = buf.sequence;
  if (last_sequence_ >= 0 && sequence > last_sequence_ + 1)
    counters_.dropped += static_cast<std::uint64_t>(sequence - last_sequence_ - 1);
  last_sequence_ = sequence;
  if ((buf.flags & V4L2_BUF_FLAG_ERROR) != 0 || buf.index >= buffers_.size()) {
    ++counters_.dropped;
    return IoStatus::kBadData;
  }
  ++counters_.frames;
  const Mapping& m = buffers_[buf.index];
  frame.pixels = std::span<const std::uint8_t>(static_cast<const std::uint8_t*>(m.address),
                                               std::min<std::size_t>(buf.bytesused, m.length));
  frame.width = width_;
  frame.height = height_;
  frame.format = format_;
  frame.camera_timestamp_ns = static_cast<std::uint64_t>(buf.timestamp.tv_sec) * 1'000'000'000ULL +
                              static_cast<std::uint64_t>(buf.timestamp.tv_usec) * 1000ULL;
  frame.host_timestamp_ns = static_cast<std::uint64_t>(MonotonicClock{}.now_ns());
  frame.frame_id = static_cast<std::uint64_t>(sequence);
  return IoStatus::kOk;
}

}  // namespace rig::drivers
