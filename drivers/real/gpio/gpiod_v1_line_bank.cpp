#include "gpiod_v1_line_bank.hpp"

#include <gpiod.h>
#include <poll.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace rig::drivers {
namespace {

// The one place where the kernel's errno becomes a cyclic status.
IoStatus status_from_errno(int error_number) noexcept {
  switch (error_number) {
    case EAGAIN:
      return IoStatus::kTimeout;
    case ENODEV:
    case ENXIO:
    case EBADF:
    case EIO:
    case ESHUTDOWN:
      return IoStatus::kLinkDown;
    case EINVAL:
    case EFAULT:
      return IoStatus::kBadData;
    default:
      return IoStatus::kLinkDown;
  }
}

constexpr std::int64_t to_ns(const timespec& ts) noexcept {
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

constexpr std::size_t kMaxInputs = 16;  // fixed poll set, no allocation in poll_edges

}  // namespace

void GpiodV1LineBank::ChipCloser::operator()(gpiod_chip* chip) const noexcept {
  gpiod_chip_close(chip);
}
void GpiodV1LineBank::LineReleaser::operator()(gpiod_line* line) const noexcept {
  gpiod_line_release(line);
}

GpiodV1LineBank::GpiodV1LineBank(const std::string& chip, const std::vector<GpioLineSpec>& inputs,
                                 const std::vector<GpioLineSpec>& outputs,
                                 const std::string& consumer)
    : chip_(gpiod_chip_open_lookup(chip.c_str())), chip_id_(chip) {
  if (!chip_)
    throw std::runtime_error("GPIO chip '" + chip + "': cannot open (" + std::strerror(errno) +
                             ")");
  if (inputs.size() > kMaxInputs) throw std::runtime_error("GPIO: at most 16 input lines");
  for (const GpioLineSpec& spec : inputs) {
    inputs_.push_back(request(spec, false, consumer));
    input_fds_.push_back(gpiod_line_event_get_fd(inputs_.back().get()));
  }
  for (const GpioLineSpec& spec : outputs) outputs_.push_back(request(spec, true, consumer));
}

GpiodV1LineBank::~GpiodV1LineBank() {
  for (auto& line : outputs_) gpiod_line_set_value(line.get(), 0);  // leave outputs inactive
}

GpiodV1LineBank::LinePtr GpiodV1LineBank::request(const GpioLineSpec& spec, bool output,
                                                  const std::string& consumer) {
  const std::string where =
      "GPIO chip '" + chip_id_ + "' line " + std::to_string(spec.offset) + " (" + spec.name + ")";
  if (spec.offset >= gpiod_chip_num_lines(chip_.get()))
    throw std::runtime_error(where + ": the chip has only " +
                             std::to_string(gpiod_chip_num_lines(chip_.get())) + " lines");
  LinePtr line(gpiod_chip_get_line(chip_.get(), spec.offset));
  if (!line) throw std::runtime_error(where + ": " + std::strerror(errno));
  gpiod_line_request_config config{};
  config.consumer = consumer.c_str();
  config.request_type =
      output ? GPIOD_LINE_REQUEST_DIRECTION_OUTPUT : GPIOD_LINE_REQUEST_EVENT_BOTH_EDGES;
  config.flags = spec.active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
  if (gpiod_line_request(line.get(), &config, 0) < 0)
    throw std::runtime_error(where + ": request failed (" + std::strerror(errno) +
                             (errno == EBUSY ? ", used by another program" : "") + ")");
  return line;
}

IoStatus GpiodV1LineBank::read_levels(std::span<bool> levels) noexcept {
  for (std::size_t i = 0; i < inputs_.size() && i < levels.size(); ++i) {
    const int value = gpiod_line_get_value(inputs_[i].get());
    if (value < 0) return status_from_errno(errno);
    levels[i] = value != 0;
  }
  return IoStatus::kOk;
}

IoStatus GpiodV1LineBank::poll_edges(std::span<LineEdge> edges, std::size_t& count) noexcept {
  count = 0;
  std::array<pollfd, kMaxInputs> fds{};
  for (std::size_t i = 0; i < input_fds_.size(); ++i) fds[i] = pollfd{input_fds_[i], POLLIN, 0};
  const int ready = ::poll(fds.data(), input_fds_.size(), 0);
  if (ready < 0) return errno == EINTR ? IoStatus::kOk : status_from_errno(errno);
  for (std::size_t i = 0; i < input_fds_.size() && count < edges.size(); ++i) {
    if ((fds[i].revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) return IoStatus::kLinkDown;
    if ((fds[i].revents & POLLIN) == 0) continue;
    std::array<gpiod_line_event, 8> events{};
    const unsigned room =
        static_cast<unsigned>(std::min<std::size_t>(events.size(), edges.size() - count));
    const int n = gpiod_line_event_read_fd_multiple(input_fds_[i], events.data(), room);
    if (n < 0) return status_from_errno(errno);
    for (int k = 0; k < n; ++k)
      edges[count++] = LineEdge{
          i, events[static_cast<std::size_t>(k)].event_type == GPIOD_LINE_EVENT_RISING_EDGE,
          to_ns(events[static_cast<std::size_t>(k)].ts)};
  }
  return IoStatus::kOk;
}

IoStatus GpiodV1LineBank::set_output(std::size_t output, bool active) noexcept {
  if (output >= outputs_.size()) return IoStatus::kNotReady;
  return gpiod_line_set_value(outputs_[output].get(), active ? 1 : 0) < 0 ? status_from_errno(errno)
                                                                          : IoStatus::kOk;
}

std::string GpiodV1LineBank::chip_name() const {
  return gpiod_chip_name(chip_.get());
}

}  // namespace rig::drivers
