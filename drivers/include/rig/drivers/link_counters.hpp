#pragma once
// Health counters of a DAQ link (Modbus TCP/RTU, USB), for /metrics and the logs.
#include <cstdint>

namespace rig::drivers {

struct LinkCounters {
  std::uint64_t transactions = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t link_errors = 0;
  std::uint64_t bad_data = 0;
  std::uint64_t reconnects = 0;
};

}  // namespace rig::drivers
