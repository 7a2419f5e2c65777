#include "usb_daq.hpp"

#include <fcntl.h>
#include <libusb-1.0/libusb.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace rig::drivers {
namespace {

std::string read_attribute(const std::filesystem::path& dir, const char* name) {
  std::ifstream in(dir / name);
  std::string value;
  std::getline(in, value);
  return value;
}

std::string hex4(int value) {
  char text[8];
  std::snprintf(text, sizeof text, "%04x", value & 0xffff);
  return text;
}

}  // namespace

void UsbDaq::ContextDeleter::operator()(libusb_context* ctx) const noexcept {
  libusb_exit(ctx);
}

UsbDaq::UsbDaq(const UsbDaqSettings& settings) : settings_(settings) {
  // No enumeration by libusb itself: without udevd it would only ever see the devices
  // present at init. We find the device in sysfs and hand libusb its usbfs descriptor.
  libusb_set_option(nullptr, LIBUSB_OPTION_NO_DEVICE_DISCOVERY);
  libusb_context* ctx = nullptr;
  if (const int r = libusb_init(&ctx); r != 0)
    throw std::runtime_error(std::string("USB DAQ: libusb_init failed: ") + libusb_error_name(r));
  ctx_.reset(ctx);
  std::string why;
  const std::string id = hex4(settings.vendor_id) + ":" + hex4(settings.product_id);
  if (!open_device(why)) throw std::runtime_error("USB DAQ " + id + ": " + why);
  usbdaq::Message reply{};
  std::span<const std::uint8_t> payload;
  // A device still answering an earlier session, or a host stalled past the time-out, can
  // miss one greeting; its late reply is skipped by the next (transact).
  IoStatus s = IoStatus::kTimeout;
  for (int attempt = 0;
       attempt < kHelloAttempts && (s == IoStatus::kTimeout || s == IoStatus::kBadData);
       ++attempt) {
    s = transact(usbdaq::Opcode::kHello, {}, reply, payload);
  }
  const auto hello = s == IoStatus::kOk ? usbdaq::decode_hello(payload) : std::nullopt;
  if (!hello) {
    close_device();
    throw std::runtime_error("USB DAQ " + id + ": no valid HELLO answer (" +
                             std::string(to_string(s)) +
                             "); is it running rigd's DAQ firmware (docs/usb-daq-protocol.md)?");
  }
  hello_ = *hello;
}

UsbDaq::~UsbDaq() {
  if (handle_ != nullptr) write(DriveCommand{});  // motor off on the way out
  close_device();
}

bool UsbDaq::open_device(std::string& why) noexcept {
  try {
    const std::string vid = hex4(settings_.vendor_id), pid = hex4(settings_.product_id);
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(settings_.sysfs_root, ec)) {
      const auto& dir = entry.path();
      if (read_attribute(dir, "idVendor") != vid || read_attribute(dir, "idProduct") != pid)
        continue;
      if (!settings_.serial.empty() && read_attribute(dir, "serial") != settings_.serial) continue;
      char node[64];
      std::snprintf(node, sizeof node, "/%03d/%03d", std::stoi(read_attribute(dir, "busnum")),
                    std::stoi(read_attribute(dir, "devnum")));
      const std::string path = settings_.devfs_root + node;
      const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
      if (fd < 0) {
        why = "cannot open " + path + " (permissions? see docs/usb-daq-protocol.md)";
        return false;
      }
      libusb_device_handle* handle = nullptr;
      if (const int r = libusb_wrap_sys_device(ctx_.get(), fd, &handle); r != 0) {
        ::close(fd);
        why = std::string("libusb_wrap_sys_device: ") + libusb_error_name(r);
        return false;
      }
      if (!find_bulk_endpoints(handle)) {
        libusb_close(handle);
        ::close(fd);
        why = "interface 0 has no bulk IN/OUT endpoint pair (not rigd's DAQ firmware?)";
        return false;
      }
      if (const int r = libusb_claim_interface(handle, 0); r != 0) {
        libusb_close(handle);
        ::close(fd);
        why = std::string("cannot claim interface 0: ") + libusb_error_name(r);
        return false;
      }
      handle_ = handle;
      device_fd_ = fd;
      have_sequence_ = false;
      // Number this session's requests from the clock, not from 1: replies the device still
      // holds for an earlier session (rigd restarted, a greeting timed out) then carry
      // sequences this one does not expect, and are skipped (transact).
      sequence_ = static_cast<std::uint16_t>(
          std::chrono::steady_clock::now().time_since_epoch().count() >> 10);
      return true;
    }
    why = "not found on the USB bus" +
          (settings_.serial.empty() ? std::string() : " with serial " + settings_.serial);
  } catch (const std::exception& e) {
    why = e.what();
  }
  return false;
}

bool UsbDaq::find_bulk_endpoints(libusb_device_handle* handle) noexcept {
  // The gadget side may renumber endpoints (FunctionFS asks the UDC), so read them back.
  libusb_config_descriptor* config = nullptr;
  if (libusb_get_active_config_descriptor(libusb_get_device(handle), &config) != 0) return false;
  ep_in_ = ep_out_ = 0;
  if (config->bNumInterfaces > 0 && config->interface[0].num_altsetting > 0) {
    const libusb_interface_descriptor& interface = config->interface[0].altsetting[0];
    for (int i = 0; i < interface.bNumEndpoints; ++i) {
      const libusb_endpoint_descriptor& ep = interface.endpoint[i];
      if ((ep.bmAttributes & 3) != LIBUSB_TRANSFER_TYPE_BULK) continue;
      ((ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) != 0 ? ep_in_ : ep_out_) = ep.bEndpointAddress;
    }
  }
  libusb_free_config_descriptor(config);
  return ep_in_ != 0 && ep_out_ != 0;
}

void UsbDaq::close_device() noexcept {
  if (handle_ != nullptr) {
    libusb_release_interface(handle_, 0);
    libusb_close(handle_);
    handle_ = nullptr;
  }
  if (device_fd_ >= 0) ::close(device_fd_);  // libusb_wrap_sys_device leaves the fd to us
  device_fd_ = -1;
}

IoStatus UsbDaq::fail(int libusb_error) noexcept {
  switch (libusb_error) {
    case LIBUSB_ERROR_TIMEOUT:
      ++counters_.timeouts;
      return IoStatus::kTimeout;
    case LIBUSB_ERROR_OVERFLOW:
      ++counters_.bad_data;
      return IoStatus::kBadData;
    default:  // NO_DEVICE, IO, PIPE, ...: treat the device as gone and look for it again
      ++counters_.link_errors;
      close_device();
      cycles_since_attempt_ = 0;
      return IoStatus::kLinkDown;
  }
}

IoStatus UsbDaq::ensure_connected() noexcept {
  if (handle_ != nullptr) return IoStatus::kOk;
  if (++cycles_since_attempt_ < settings_.reconnect_every_cycles) return IoStatus::kLinkDown;
  cycles_since_attempt_ = 0;
  std::string why;
  if (!open_device(why)) return IoStatus::kLinkDown;
  ++counters_.reconnects;
  return IoStatus::kOk;
}

IoStatus UsbDaq::transact(usbdaq::Opcode opcode, std::span<const std::uint8_t> payload,
                          usbdaq::Message& reply,
                          std::span<const std::uint8_t>& reply_payload) noexcept {
  if (handle_ == nullptr) return IoStatus::kLinkDown;
  usbdaq::Message request{};
  const std::uint16_t sequence = ++sequence_;
  const std::size_t length = usbdaq::encode_request(request, opcode, sequence, payload);
  ++counters_.transactions;
  int sent = 0, got = 0;
  if (const int r = libusb_bulk_transfer(handle_, ep_out_, request.data(), static_cast<int>(length),
                                         &sent, settings_.timeout_ms);
      r != 0)
    return fail(r);
  // Replies to earlier requests that timed out may still be queued, whatever they answered:
  // skip every other sequence.
  for (int attempt = 0; attempt < kStaleRepliesSkipped; ++attempt) {
    if (const int r =
            libusb_bulk_transfer(handle_, ep_in_, reply.data(), static_cast<int>(reply.size()),
                                 &got, settings_.timeout_ms);
        r != 0)
      return fail(r);
    const auto header = usbdaq::decode_header(
        std::span<const std::uint8_t>(reply.data(), static_cast<std::size_t>(got)));
    if (!header || !header->response) {
      ++counters_.bad_data;
      return IoStatus::kBadData;
    }
    if (header->sequence != sequence) continue;
    if (header->opcode != opcode) {
      ++counters_.bad_data;
      return IoStatus::kBadData;
    }
    if (header->status != usbdaq::Status::kOk) {
      ++counters_.bad_data;
      return IoStatus::kRefused;
    }
    reply_payload =
        std::span<const std::uint8_t>(reply.data() + usbdaq::kHeaderSize, header->length);
    return IoStatus::kOk;
  }
  ++counters_.bad_data;
  return IoStatus::kBadData;
}

IoStatus UsbDaq::read(AnalogFrame& frame) noexcept {
  input_status_ = ensure_connected();
  if (input_status_ != IoStatus::kOk) return input_status_;
  usbdaq::Message reply{};
  std::span<const std::uint8_t> payload;
  input_status_ = transact(usbdaq::Opcode::kReadInputs, {}, reply, payload);
  if (input_status_ != IoStatus::kOk) return input_status_;
  const auto inputs = usbdaq::decode_inputs(payload);
  const auto plausible = [this](float v) {
    return std::isfinite(v) && std::fabs(v) <= settings_.max_abs_volts;
  };
  if (!inputs || !plausible(inputs->force_volts) || !plausible(inputs->position_volts) ||
      !plausible(inputs->iop_volts)) {
    ++counters_.bad_data;
    return input_status_ = IoStatus::kBadData;
  }
  if (have_sequence_ && inputs->sequence == last_sequence_) return input_status_ = IoStatus::kStale;
  have_sequence_ = true;
  last_sequence_ = inputs->sequence;
  inputs_ = *inputs;
  watchdog_tripped_ = (inputs_.flags & 1U) != 0;
  frame.force_volts = inputs_.force_volts;
  frame.position_volts = inputs_.position_volts;
  frame.iop_volts = inputs_.iop_volts;
  frame.sequence = inputs_.sequence;
  return IoStatus::kOk;
}

IoStatus UsbDaq::read(DigitalInputs& inputs) noexcept {
  if (input_status_ != IoStatus::kOk) return input_status_;
  inputs.home_limit = (inputs_.digital & 1U) != 0;
  inputs.end_limit = (inputs_.digital & 2U) != 0;
  inputs.estop = (inputs_.digital & 4U) != 0;
  inputs.drive_fault = (inputs_.digital & 8U) != 0;
  inputs.daq_watchdog_tripped = watchdog_tripped_;  // flags bit 0 of the same reply
  return IoStatus::kOk;
}

IoStatus UsbDaq::write(const DigitalOutputs& outputs) noexcept {
  staged_outputs_ = outputs;
  return IoStatus::kOk;
}

IoStatus UsbDaq::write(const DriveCommand& command) noexcept {
  if (handle_ == nullptr) return IoStatus::kLinkDown;
  usbdaq::OutputsRequest out;
  const bool enable = command.motor_enable && staged_outputs_.motor_enable;
  out.digital =
      static_cast<std::uint16_t>((enable ? 1U : 0U) | (staged_outputs_.camera_trigger ? 2U : 0U));
  out.watchdog_ms = static_cast<std::uint16_t>(settings_.watchdog_ms);
  out.motor_volts = enable ? static_cast<float>(command.motor_volts) : 0.0F;
  out.pump_command = static_cast<float>(command.pump_command);
  const auto payload = usbdaq::encode(out);
  usbdaq::Message reply{};
  std::span<const std::uint8_t> reply_payload;
  return transact(usbdaq::Opcode::kWriteOutputs, payload, reply, reply_payload);
}

}  // namespace rig::drivers
