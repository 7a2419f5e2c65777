#pragma once
// A USB function in user space through the kernel's FunctionFS: one vendor-specific
// interface with a bulk IN and a bulk OUT endpoint (64 B full speed, 512 B high speed).
// Requests from the host's OUT endpoint go to a handler, its answer to the IN endpoint.
// Survives the UDC being unbound and bound again (a cable pulled and plugged back).
#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <thread>

#include "usb/usb_daq_protocol.hpp"

namespace rig::sim {

class FunctionFsGadget {
 public:
  using Handler =
      std::function<std::size_t(std::span<const std::uint8_t>, drivers::usbdaq::Message&)>;

  // dir: where the function's FunctionFS instance is mounted. Writes the descriptors and
  // opens the endpoints; throws naming the file (setup only).
  FunctionFsGadget(const std::string& dir, Handler handler);
  ~FunctionFsGadget();
  FunctionFsGadget(const FunctionFsGadget&) = delete;
  FunctionFsGadget& operator=(const FunctionFsGadget&) = delete;

  // Serves requests until stop() (from another thread or a signal handler's flag).
  void serve(const std::atomic<bool>& stop);

 private:
  void watch_ep0();

  std::string dir_;
  Handler handler_;
  int ep0_ = -1, ep_in_ = -1, ep_out_ = -1;
  std::atomic<bool> closing_{false};
  std::thread ep0_thread_;
};

}  // namespace rig::sim
