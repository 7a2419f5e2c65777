#include "modbus_context.hpp"

#include <modbus/modbus.h>

#include <cerrno>
#include <stdexcept>

namespace rig::drivers {

void ModbusContextDeleter::operator()(_modbus* ctx) const noexcept {
  modbus_close(ctx);
  modbus_free(ctx);
}

ModbusContextPtr make_modbus_tcp(const std::string& host, int port) {
  ModbusContextPtr ctx(modbus_new_tcp(host.c_str(), port));
  if (!ctx)
    throw std::runtime_error("modbus: cannot create TCP context for " + host + ":" +
                             std::to_string(port) + ": " + modbus_strerror(errno));
  return ctx;
}

ModbusContextPtr make_modbus_rtu(const std::string& device, int baud, char parity, int data_bits,
                                 int stop_bits) {
  ModbusContextPtr ctx(modbus_new_rtu(device.c_str(), baud, parity, data_bits, stop_bits));
  if (!ctx)
    throw std::runtime_error("modbus: cannot create RTU context for " + device + ": " +
                             modbus_strerror(errno));
  return ctx;
}

IoStatus io_status_from_errno(int error_number) noexcept {
  switch (error_number) {
    case ETIMEDOUT:
    case EAGAIN:
      return IoStatus::kTimeout;
    case ECONNRESET:
    case ECONNREFUSED:
    case ECONNABORTED:
    case EPIPE:
    case EBADF:
    case ENOTCONN:
    case EHOSTUNREACH:
    case ENETUNREACH:
    case EIO:
    case ENODEV:
    case ENXIO:
      return IoStatus::kLinkDown;
    default:
      // EMBXILFUN ... EMBXGTAR: the DAQ answered in step and said no (e.g. exception 4).
      if (error_number > MODBUS_ENOBASE && error_number < MODBUS_ENOBASE + MODBUS_EXCEPTION_MAX)
        return IoStatus::kRefused;
      // EMBBADDATA, EMBBADCRC, EMBBADEXC, EMBMDATA, EMBXILFUN, ...: the peer answered
      // something we cannot use.
      return IoStatus::kBadData;
  }
}

}  // namespace rig::drivers
