// rig-sim's heartbeat (sim/server/heartbeat_writer.hpp): one line per period on a descriptor,
// saying when the line was written and how long before that the last DAQ read arrived.
#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <string>

#include "heartbeat_writer.hpp"

namespace rig::sim {
namespace {

constexpr std::int64_t kMs = 1'000'000;  // [ns]

class HeartbeatWriterTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(pipe(fds_.data()), 0); }
  void TearDown() override {
    close(fds_[0]);
    close(fds_[1]);
  }
  std::string read_all() {
    fcntl(fds_[0], F_SETFL, fcntl(fds_[0], F_GETFL) | O_NONBLOCK);
    std::string text;
    std::array<char, 4096> buffer{};
    for (ssize_t n; (n = read(fds_[0], buffer.data(), buffer.size())) > 0;)
      text.append(buffer.data(), static_cast<std::size_t>(n));
    return text;
  }
  std::array<int, 2> fds_{};
};

TEST_F(HeartbeatWriterTest, writes_one_line_per_period_with_the_time_and_the_age_of_the_last_read) {
  HeartbeatWriter heartbeat(fds_[1], 5);
  heartbeat.tick(10 * kMs);  // no read yet: age -1
  heartbeat.note_read_request(12 * kMs);
  heartbeat.tick(13 * kMs);  // within the period: nothing
  heartbeat.tick(15 * kMs + 250'000);
  EXPECT_EQ(read_all(), "10000 -1\n15250 3250\n");
  EXPECT_EQ(heartbeat.written(), 2U);
  EXPECT_EQ(heartbeat.dropped(), 0U);
}

TEST_F(HeartbeatWriterTest, drops_lines_instead_of_blocking_when_nobody_reads) {
  HeartbeatWriter heartbeat(fds_[1], 1);
  fcntl(fds_[1], F_SETPIPE_SZ, 4096);
  for (int i = 1; i <= 2000; ++i)
    heartbeat.tick(i * kMs);  // ~16 kB into a 4 kB pipe: must not block
  EXPECT_GT(heartbeat.dropped(), 0U);
  EXPECT_EQ(heartbeat.written() + heartbeat.dropped(), 2000U);
  const std::string text = read_all();
  EXPECT_EQ(text.back(), '\n');  // whole lines only
}

TEST_F(HeartbeatWriterTest, is_off_without_a_descriptor_and_refuses_a_closed_one) {
  HeartbeatWriter off(-1, 5);
  off.tick(100 * kMs);
  EXPECT_FALSE(off.enabled());
  EXPECT_EQ(off.written(), 0U);
  const int closed = dup(fds_[1]);
  close(closed);
  EXPECT_THROW(HeartbeatWriter(closed, 5), std::runtime_error);
}

}  // namespace
}  // namespace rig::sim
