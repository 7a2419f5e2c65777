#pragma once
// The simulated rig's test panel and ground truth, over Modbus (as any client would).
#include <modbus/modbus.h>

#include <stdexcept>
#include <string>

#include "rig/proto/daq_register_map.hpp"

namespace rig::testing {

class SimPanel {
 public:
  explicit SimPanel(int port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    modbus_set_slave(ctx_, proto::daq::kUnitId);
    modbus_set_response_timeout(ctx_, 1, 0);
    if (modbus_connect(ctx_) != 0)
      throw std::runtime_error("cannot connect to rig-sim on port " + std::to_string(port));
  }
  ~SimPanel() {
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
  SimPanel(const SimPanel&) = delete;
  SimPanel& operator=(const SimPanel&) = delete;

  void set(int reg, std::uint16_t value) {
    if (modbus_write_register(ctx_, reg, value) != 1)
      throw std::runtime_error("panel write failed: " + std::string(modbus_strerror(errno)));
  }
  void set_float(int reg, float value) {
    std::uint16_t words[2];
    proto::daq::encode_f32(value, words);
    if (modbus_write_registers(ctx_, reg, 2, words) != 2)
      throw std::runtime_error("panel write failed");
  }
  std::uint16_t input(int reg) {
    std::uint16_t value = 0;
    if (modbus_read_input_registers(ctx_, reg, 1, &value) != 1)
      throw std::runtime_error("truth read failed");
    return value;
  }
  double input_float(int reg) {
    std::uint16_t words[2];
    if (modbus_read_input_registers(ctx_, reg, 2, words) != 2)
      throw std::runtime_error("truth read failed");
    return proto::daq::decode_f32(words);
  }
  double input_u32(int reg) {
    std::uint16_t words[2];
    if (modbus_read_input_registers(ctx_, reg, 2, words) != 2)
      throw std::runtime_error("truth read failed");
    return proto::daq::decode_u32(words);
  }
  bool motor_powered() { return input(proto::daq::sim_truth::kMotorPowered) != 0; }
  double motor_off_time_s() { return input_u32(proto::daq::sim_truth::kMotorOffTimeUs) * 1e-6; }
  double sim_time_s() { return input_u32(proto::daq::sim_truth::kSimTimeUs) * 1e-6; }
  double motor_off_silence_s() {
    return input_u32(proto::daq::sim_truth::kMotorOffSilenceUs) * 1e-6;
  }

 private:
  modbus_t* ctx_;
};

}  // namespace rig::testing
