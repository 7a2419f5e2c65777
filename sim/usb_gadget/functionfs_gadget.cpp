#include "functionfs_gadget.hpp"

#include <fcntl.h>
#include <linux/usb/ch9.h>
#include <linux/usb/functionfs.h>
#include <poll.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace rig::sim {
namespace {

struct __attribute__((packed)) InterfaceDescriptors {
  usb_interface_descriptor interface;
  usb_endpoint_descriptor_no_audio in;
  usb_endpoint_descriptor_no_audio out;
};

constexpr InterfaceDescriptors interface_descriptors(std::uint16_t max_packet) {
  InterfaceDescriptors d{};
  d.interface = {
      sizeof(usb_interface_descriptor), USB_DT_INTERFACE, 0, 0, 2, USB_CLASS_VENDOR_SPEC, 0, 0, 1};
  d.in = {USB_DT_ENDPOINT_SIZE,   USB_DT_ENDPOINT, 1 | USB_DIR_IN,
          USB_ENDPOINT_XFER_BULK, max_packet,      0};
  d.out = {USB_DT_ENDPOINT_SIZE,   USB_DT_ENDPOINT, 2 | USB_DIR_OUT,
           USB_ENDPOINT_XFER_BULK, max_packet,      0};
  return d;
}

struct __attribute__((packed)) Descriptors {
  usb_functionfs_descs_head_v2 header;
  std::uint32_t full_speed_count, high_speed_count;
  InterfaceDescriptors full_speed, high_speed;
};

constexpr char kInterfaceName[] = "rigd USB DAQ";
struct __attribute__((packed)) Strings {
  usb_functionfs_strings_head header;
  std::uint16_t language;
  char text[sizeof(kInterfaceName)];
};

int open_or_throw(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path + ": " + std::strerror(errno));
  return fd;
}

void write_or_throw(int fd, const void* data, std::size_t size, const std::string& what) {
  if (::write(fd, data, size) != static_cast<ssize_t>(size))
    throw std::runtime_error(what + ": " + std::strerror(errno));
}

}  // namespace

FunctionFsGadget::FunctionFsGadget(const std::string& dir, Handler handler)
    : dir_(dir), handler_(std::move(handler)) {
  ep0_ = open_or_throw(dir + "/ep0");
  Descriptors d{};
  d.header = {FUNCTIONFS_DESCRIPTORS_MAGIC_V2, sizeof(Descriptors),
              FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC};
  d.full_speed_count = 3;
  d.high_speed_count = 3;
  d.full_speed = interface_descriptors(64);
  d.high_speed = interface_descriptors(512);
  write_or_throw(ep0_, &d, sizeof d, dir + "/ep0 descriptors");
  Strings s{};
  s.header = {FUNCTIONFS_STRINGS_MAGIC, sizeof(Strings), 1, 1};
  s.language = 0x0409;
  std::memcpy(s.text, kInterfaceName, sizeof kInterfaceName);
  write_or_throw(ep0_, &s, sizeof s, dir + "/ep0 strings");
  ep_in_ = open_or_throw(dir + "/ep1");
  ep_out_ = open_or_throw(dir + "/ep2");
  ep0_thread_ = std::thread([this] { watch_ep0(); });
}

FunctionFsGadget::~FunctionFsGadget() {
  closing_.store(true);
  if (ep0_thread_.joinable()) ep0_thread_.join();
  ::close(ep_in_);
  ::close(ep_out_);
  ::close(ep0_);
}

void FunctionFsGadget::watch_ep0() {
  std::array<usb_functionfs_event, 4> events{};
  while (!closing_.load()) {
    pollfd pfd{ep0_, POLLIN, 0};
    if (::poll(&pfd, 1, 100) <= 0) continue;
    const ssize_t n = ::read(ep0_, events.data(), sizeof events);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) return;
    for (std::size_t i = 0; i < static_cast<std::size_t>(n) / sizeof events[0]; ++i) {
      if (events[i].type != FUNCTIONFS_SETUP) continue;
      // No control requests are defined: stall them (a zero-length transfer the wrong way).
      if ((events[i].u.setup.bRequestType & USB_DIR_IN) != 0)
        (void)!::write(ep0_, nullptr, 0);
      else
        (void)!::read(ep0_, nullptr, 0);
    }
  }
}

void FunctionFsGadget::serve(const std::atomic<bool>& stop) {
  std::array<std::uint8_t, 512> request{};
  drivers::usbdaq::Message response{};
  while (!stop.load()) {
    pollfd pfd{ep_out_, POLLIN, 0};
    if (::poll(&pfd, 1, 100) <= 0) continue;
    const ssize_t n = ::read(ep_out_, request.data(), request.size());
    if (n < 0) {
      // ESHUTDOWN while the host is gone (UDC unbound, cable pulled): wait for it.
      if (errno == EINTR || errno == ESHUTDOWN || errno == EAGAIN) {
        ::usleep(1000);
        continue;
      }
      throw std::runtime_error(dir_ + "/ep2: " + std::strerror(errno));
    }
    const std::size_t length = handler_(
        std::span<const std::uint8_t>(request.data(), static_cast<std::size_t>(n)), response);
    if (length > 0 && ::write(ep_in_, response.data(), length) < 0 && errno != ESHUTDOWN)
      throw std::runtime_error(dir_ + "/ep1: " + std::strerror(errno));
  }
}

}  // namespace rig::sim
