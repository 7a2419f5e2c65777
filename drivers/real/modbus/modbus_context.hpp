#pragma once
// RAII owner of a libmodbus context (libgpiod-C++ style: the C handle lives in a
// unique_ptr with a deleter) and the one place where libmodbus errno becomes IoStatus.
#include <memory>
#include <string>

#include "rig/drivers/io_status.hpp"

// The C library's own struct tags, declared here so the header need not include it.
// NOLINTBEGIN(bugprone-reserved-identifier)
struct _modbus;
// NOLINTEND(bugprone-reserved-identifier)

namespace rig::drivers {

struct ModbusContextDeleter {
  void operator()(_modbus* ctx) const noexcept;
};
using ModbusContextPtr = std::unique_ptr<_modbus, ModbusContextDeleter>;

// TCP context to host:port; throws std::runtime_error (setup only) if it cannot be created.
ModbusContextPtr make_modbus_tcp(const std::string& host, int port);
// RTU context on a serial device; throws std::runtime_error (setup only).
ModbusContextPtr make_modbus_rtu(const std::string& device, int baud, char parity, int data_bits,
                                 int stop_bits);

// Maps errno after a failed libmodbus call. Link errors mean the socket must be reopened.
IoStatus io_status_from_errno(int error_number) noexcept;

}  // namespace rig::drivers
