#include "usb_daq_device.hpp"

namespace rig::sim {

namespace usbdaq = drivers::usbdaq;

std::size_t UsbDaqDevice::handle(std::span<const std::uint8_t> request, usbdaq::Message& response,
                                 double now_s) {
  const auto header = usbdaq::decode_header(request);
  if (!header || header->response) return 0;
  const std::lock_guard lock(mutex_);
  ++requests_;
  physics_->advance_to(now_s);
  const auto payload = request.subspan(usbdaq::kHeaderSize);
  switch (header->opcode) {
    case usbdaq::Opcode::kHello: {
      if (!payload.empty())
        return usbdaq::encode_response(response, *header, usbdaq::Status::kBadLength);
      const auto reply = usbdaq::encode(usbdaq::HelloReply{});
      return usbdaq::encode_response(response, *header, usbdaq::Status::kOk, reply);
    }
    case usbdaq::Opcode::kReadInputs: {
      if (!payload.empty())
        return usbdaq::encode_response(response, *header, usbdaq::Status::kBadLength);
      const drivers::AnalogFrame frame = physics_->analog_frame();
      const drivers::DigitalInputs in = physics_->digital_inputs();
      usbdaq::InputsReply reply;
      reply.sequence = ++conversions_;
      reply.force_volts = static_cast<float>(frame.force_volts);
      reply.position_volts = static_cast<float>(frame.position_volts);
      reply.iop_volts = static_cast<float>(frame.iop_volts);
      reply.digital =
          static_cast<std::uint16_t>((in.home_limit ? 1U : 0U) | (in.end_limit ? 2U : 0U) |
                                     (in.estop ? 4U : 0U) | (in.drive_fault ? 8U : 0U));
      reply.flags = physics_->truth().watchdog_tripped ? 1U : 0U;
      return usbdaq::encode_response(response, *header, usbdaq::Status::kOk, usbdaq::encode(reply));
    }
    case usbdaq::Opcode::kWriteOutputs: {
      const auto out = usbdaq::decode_outputs(payload);
      if (!out) return usbdaq::encode_response(response, *header, usbdaq::Status::kBadLength);
      physics_->set_watchdog_ms(out->watchdog_ms);
      drivers::DriveCommand drive;
      drive.motor_enable = (out->digital & 1U) != 0;
      drive.motor_volts = out->motor_volts;
      drive.pump_command = out->pump_command;
      drivers::DigitalOutputs digital;
      digital.motor_enable = drive.motor_enable;
      digital.camera_trigger = (out->digital & 2U) != 0;
      physics_->write_outputs(drive, digital);
      return usbdaq::encode_response(response, *header, usbdaq::Status::kOk);
    }
  }
  return usbdaq::encode_response(response, *header, usbdaq::Status::kUnknownOpcode);
}

}  // namespace rig::sim
