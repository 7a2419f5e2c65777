#pragma once
// GpioLineBank on libgpiod 1.6 (the v1 C API). Every C handle is owned by a unique_ptr
// with its deleter; errno is turned into IoStatus in one place (status_from_errno).
#include <memory>
#include <string>
#include <vector>

#include "gpio_line_bank.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace rig::drivers {

struct GpioLineSpec {
  unsigned offset = 0;      // line number on the chip
  bool active_low = false;  // logical 1 = electrical low (normally-closed contacts)
  std::string name;         // for error messages: "e-stop", "home limit", ...
};

class GpiodV1LineBank final : public GpioLineBank {
 public:
  // Opens the chip (name, /dev path, label or number) and requests every line; throws
  // std::runtime_error naming the chip, line and reason (setup only).
  GpiodV1LineBank(const std::string& chip, const std::vector<GpioLineSpec>& inputs,
                  const std::vector<GpioLineSpec>& outputs, const std::string& consumer = "rigd");
  ~GpiodV1LineBank() override;

  IoStatus read_levels(std::span<bool> levels) noexcept override;
  IoStatus poll_edges(std::span<LineEdge> edges, std::size_t& count) noexcept override;
  IoStatus set_output(std::size_t output, bool active) noexcept override;
  std::string chip_name() const;

 private:
  struct ChipCloser {
    void operator()(gpiod_chip* chip) const noexcept;
  };
  struct LineReleaser {
    void operator()(gpiod_line* line) const noexcept;
  };
  using ChipPtr = std::unique_ptr<gpiod_chip, ChipCloser>;
  using LinePtr = std::unique_ptr<gpiod_line, LineReleaser>;

  LinePtr request(const GpioLineSpec& spec, bool output, const std::string& consumer);

  ChipPtr chip_;
  std::string chip_id_;
  std::vector<LinePtr> inputs_;
  std::vector<int> input_fds_;  // event file descriptors, polled together
  std::vector<LinePtr> outputs_;
};

}  // namespace rig::drivers
