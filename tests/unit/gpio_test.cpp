// GPIO inputs and outputs above the kernel: the debounce policy, the e-stop's own hold on
// motor power, and a clear error for a chip that is not there. The same driver runs
// against the kernel's gpio-sim in tests/kernel (label `kernel`).
#include <gtest/gtest.h>

#include <array>
#include <memory>

#include "gpio/gpio_digital_io.hpp"
#include "gpio/input_debouncer.hpp"
#include "rig/drivers/loop_clock.hpp"
#include "sim_gpio_line_bank.hpp"

namespace rig::drivers {
namespace {

constexpr std::int64_t kMs = 1'000'000;

// Time moves only when the test sleeps [ns].
class ManualClock final : public LoopClock {
 public:
  std::int64_t now_ns() noexcept override { return now_; }
  void sleep_until(std::int64_t deadline_ns) noexcept override {
    now_ = std::max(now_, deadline_ns);
  }

 private:
  std::int64_t now_ = 1'000'000'000;
};

TEST(InputDebouncer, BelievesAnActivationAtOnce) {
  InputDebouncer d(2 * kMs);
  const std::array<bool, 1> idle{false};
  d.reset(idle, 0);
  d.on_edge(0, true, 10 * kMs);
  EXPECT_TRUE(d.read(0, 10 * kMs));
}

TEST(InputDebouncer, ReportsARelease_OnlyAfterTheLineStayedInactiveForTheDebounceTime) {
  InputDebouncer d(2 * kMs);
  const std::array<bool, 1> pressed{true};
  d.reset(pressed, 0);
  d.on_edge(0, false, 10 * kMs);
  EXPECT_TRUE(d.read(0, 11 * kMs));
  EXPECT_FALSE(d.read(0, 12 * kMs));
}

TEST(InputDebouncer, IgnoresContactBounceOnRelease) {
  InputDebouncer d(2 * kMs);
  const std::array<bool, 1> pressed{true};
  d.reset(pressed, 0);
  d.on_edge(0, false, 10 * kMs);
  d.on_edge(0, true, 10 * kMs + 300'000);  // bounce
  d.on_edge(0, false, 10 * kMs + 600'000);
  EXPECT_TRUE(d.read(0, 12 * kMs));  // 1.4 ms since the last bounce
  EXPECT_FALSE(d.read(0, 13 * kMs));
}

TEST(InputDebouncer, LatchesAPressShorterThanOneReadPeriod) {
  InputDebouncer d(0);
  const std::array<bool, 1> idle{false};
  d.reset(idle, 0);
  d.on_edge(0, true, 1 * kMs);
  d.on_edge(0, false, 1 * kMs + 50'000);  // released 50 us later, before anyone read
  EXPECT_TRUE(d.read(0, 2 * kMs)) << "the press must be seen once";
  EXPECT_FALSE(d.read(0, 3 * kMs));
}

// Found in the QEMU tier on a loaded machine: gpio-sim's press and release, 1 us apart, both
// came as edges labelled inactive (the kernel read the line after the release).
TEST(InputDebouncer, APulseTheKernelLabelledInactiveTwiceIsStillAPress) {
  InputDebouncer d(2 * kMs);
  const std::array<bool, 1> idle{false};
  d.reset(idle, 0);
  d.on_edge(0, false, 1 * kMs);
  d.on_edge(0, false, 1 * kMs + 1'000);
  EXPECT_TRUE(d.read(0, 2 * kMs)) << "the press must be seen once";
  EXPECT_FALSE(d.read(0, 3 * kMs));
}

// Found in the QEMU tier under load: a bounce on release whose edges the kernel labelled
// inactive twice. The line was active in between, so the release is timed from the second.
TEST(InputDebouncer, ABounceTheKernelLabelledInactiveTwiceRestartsTheReleaseTime) {
  InputDebouncer d(2 * kMs);
  const std::array<bool, 1> pressed{true};
  d.reset(pressed, 0);
  d.on_edge(0, false, 10 * kMs);
  d.on_edge(0, false, 10 * kMs + 600'000);  // bounce, labelled after it ended
  EXPECT_TRUE(d.read(0, 12 * kMs));         // the bounce's latch
  EXPECT_TRUE(d.read(0, 12 * kMs + 300'000)) << "1.7 ms since the bounce: still pressed";
  EXPECT_FALSE(d.read(0, 13 * kMs));
}

struct GpioFixture : ::testing::Test {
  ManualClock clock;
  SimGpioLineBank* bank = nullptr;
  std::unique_ptr<GpioDigitalIo> io;
  void SetUp() override {
    auto owned = std::make_unique<SimGpioLineBank>();
    bank = owned.get();
    io = std::make_unique<GpioDigitalIo>(std::move(owned), true, 2 * kMs, clock);
  }
};

TEST_F(GpioFixture, ReportsEachInputOnItsOwnField) {
  DigitalInputs in;
  ASSERT_EQ(io->read(in), IoStatus::kOk);
  EXPECT_FALSE(in.home_limit || in.end_limit || in.estop || in.drive_fault);
  bank->set_input(kEndInput, true, clock.now_ns());
  bank->set_input(kDriveFaultInput, true, clock.now_ns());
  ASSERT_EQ(io->read(in), IoStatus::kOk);
  EXPECT_TRUE(in.end_limit);
  EXPECT_TRUE(in.drive_fault);
  EXPECT_FALSE(in.home_limit);
  EXPECT_FALSE(in.estop);
}

TEST_F(GpioFixture, DrivesTheMotorEnableAndTriggerLines) {
  DigitalInputs in;
  io->read(in);
  ASSERT_EQ(io->write(DigitalOutputs{true, true}), IoStatus::kOk);
  EXPECT_TRUE(bank->output(kMotorEnableOutput));
  EXPECT_TRUE(bank->output(kCameraTriggerOutput));
  io->write(DigitalOutputs{false, false});
  EXPECT_FALSE(bank->output(kMotorEnableOutput));
  EXPECT_FALSE(bank->output(kCameraTriggerOutput));
}

TEST_F(GpioFixture, AnEstopEdgeCutsMotorEnableAtTheNextRead_WhateverTheLoopAsksFor) {
  DigitalInputs in;
  io->read(in);
  io->write(DigitalOutputs{true, false});
  ASSERT_TRUE(bank->output(kMotorEnableOutput));
  bank->set_input(kEstopInput, true, clock.now_ns());
  io->read(in);
  EXPECT_TRUE(in.estop);
  EXPECT_FALSE(bank->output(kMotorEnableOutput)) << "read() itself drops motor enable";
  io->write(DigitalOutputs{true, false});
  EXPECT_FALSE(bank->output(kMotorEnableOutput))
      << "the loop cannot re-enable while the e-stop is pressed";
  bank->set_input(kEstopInput, false, clock.now_ns());
  clock.sleep_until(clock.now_ns() + 3 * kMs);
  io->read(in);
  EXPECT_FALSE(in.estop);
  io->write(DigitalOutputs{true, false});
  EXPECT_TRUE(bank->output(kMotorEnableOutput));
}

TEST(GpioDigitalIoSetup, AMissingChipIsAnErrorNamingIt) {
  ManualClock clock;
  GpioSettings settings;
  settings.chip = "no-such-gpiochip";
  try {
    GpioDigitalIo io(settings, clock);
    FAIL() << "opened a chip that does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-gpiochip"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rig::drivers
