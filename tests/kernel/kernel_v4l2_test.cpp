// The V4L2 camera driver against the kernel's vivid driver (run inside the QEMU VM by
// scenario_v4l2.sh): format negotiation, memory-mapped streaming, kernel time stamps on
// the host clock, and the archive path (per-run frame file + index, frames tied to samples).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include "archive.hpp"
#include "camera/v4l2_camera.hpp"
#include "clock/monotonic_clock.hpp"
#include "frame_file.hpp"
#include "kernel_env.hpp"

namespace rig::kernel_tests {
namespace {

using drivers::FrameView;
using drivers::IoStatus;

struct Vivid : ::testing::Test {
  std::string device = env_or_empty("RIG_VIDEO");
  drivers::CameraSettings settings;
  void SetUp() override {
    ASSERT_FALSE(device.empty())
        << "RIG_VIDEO not set: run inside the kernel VM (scenario_v4l2.sh)";
    settings.width = 640;
    settings.height = 480;
    settings.frame_rate_hz = 25.0;
    settings.pixel_format = drivers::PixelFormat::kYuyv;
    settings.buffer_count = 4;
  }
};

TEST_F(Vivid, NegotiatesTheRequestedFormatSizeAndRate) {
  {
    drivers::V4l2Camera camera(device, settings);
    EXPECT_EQ(camera.width(), 640);
    EXPECT_EQ(camera.height(), 480);
    EXPECT_EQ(camera.format(), drivers::PixelFormat::kYuyv);
    EXPECT_NEAR(camera.frame_rate_hz(), 25.0, 0.5);
    EXPECT_NE(camera.describe().find("vivid"), std::string::npos) << camera.describe();
  }
  settings.pixel_format = drivers::PixelFormat::kMono8;
  drivers::V4l2Camera grey(device, settings);
  EXPECT_EQ(grey.format(), drivers::PixelFormat::kMono8);
}

TEST_F(Vivid, StreamsFramesWithRisingSequenceAndKernelTimestampsOnTheHostClock) {
  drivers::V4l2Camera camera(device, settings);
  ASSERT_TRUE(camera.monotonic_timestamps());
  ASSERT_EQ(camera.start(), IoStatus::kOk);
  std::uint64_t last_id = 0, last_ts = 0;
  for (int i = 0; i < 15; ++i) {
    FrameView f;
    ASSERT_EQ(camera.next_frame(f, 2'000'000), IoStatus::kOk) << "frame " << i;
    EXPECT_EQ(f.pixels.size(), 640U * 480U * 2U);
    if (i > 0) {
      EXPECT_GT(f.frame_id, last_id);
      EXPECT_GT(f.camera_timestamp_ns, last_ts);
    }
    // Same time line: vivid stamps each frame with its nominal time, which can lead its
    // delivery by up to a frame period; a UVC camera stamps the start of the frame.
    const auto skew_ns = static_cast<std::int64_t>(f.host_timestamp_ns) -
                         static_cast<std::int64_t>(f.camera_timestamp_ns);
    EXPECT_LT(std::abs(skew_ns), 200'000'000) << "kernel time stamp and host clock disagree";
    last_id = f.frame_id;
    last_ts = f.camera_timestamp_ns;
  }
  EXPECT_EQ(camera.counters().frames, 15U);
  EXPECT_EQ(camera.stop(), IoStatus::kOk);
}

TEST_F(Vivid, FramesGoToTheRunsFrameFileIndexedByTheSampleOfTheirTimestamp) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rig-v4l2";
  std::filesystem::create_directories(dir);
  archive::Archive store((dir / "archive.sqlite").string());
  const std::int64_t run = store.create_run(archive::NewRun{});
  archive::FrameFile file((dir / "run.frames").string());
  drivers::V4l2Camera camera(device, settings);
  constexpr std::int64_t kPeriod_ns = 1'000'000;  // a 1 kHz loop that started now
  const std::int64_t loop_start_ns = drivers::MonotonicClock{}.now_ns();
  ASSERT_EQ(camera.start(), IoStatus::kOk);
  std::vector<std::vector<std::uint8_t>> kept;
  for (int i = 0; i < 10; ++i) {
    FrameView f;
    ASSERT_EQ(camera.next_frame(f, 2'000'000), IoStatus::kOk);
    archive::FrameRow row;
    row.run_id = run;
    row.frame_no = i;
    row.sample_index =
        (static_cast<std::int64_t>(f.camera_timestamp_ns) - loop_start_ns) / kPeriod_ns;
    row.camera_ts_ns = static_cast<std::int64_t>(f.camera_timestamp_ns);
    row.host_ts_ns = static_cast<std::int64_t>(f.host_timestamp_ns);
    row.file_offset = file.append(f.pixels);
    row.bytes = static_cast<std::int64_t>(f.pixels.size());
    row.width = f.width;
    row.height = f.height;
    row.file = file.path();
    store.add_frame(row);
    kept.emplace_back(f.pixels.begin(), f.pixels.end());
  }
  file.flush();
  const auto rows = store.run_frames(run);
  ASSERT_EQ(rows.size(), 10U);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const std::int64_t gap = rows[i].sample_index - rows[i - 1].sample_index;
    EXPECT_GE(gap, 20) << "25 Hz frames are ~40 samples apart at 1 kHz";
    EXPECT_LE(gap, 130);
  }
  std::ifstream in(rows[7].file, std::ios::binary);
  in.seekg(rows[7].file_offset);
  std::vector<std::uint8_t> back(static_cast<std::size_t>(rows[7].bytes));
  in.read(reinterpret_cast<char*>(back.data()), static_cast<std::streamsize>(back.size()));
  EXPECT_EQ(back, kept[7]) << "pixels read back from the frame file";
}

TEST_F(Vivid, ACameraAlreadyStreamingElsewhereIsAnErrorSayingSo) {
  drivers::V4l2Camera first(device, settings);
  try {
    drivers::V4l2Camera second(device, settings);
    FAIL() << "two owners of one camera";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("in use"), std::string::npos) << e.what();
  }
}

TEST_F(Vivid, ANodeThatIsNotACameraIsAnErrorNamingIt) {
  try {
    drivers::V4l2Camera camera("/dev/null", settings);
    FAIL() << "/dev/null accepted as a camera";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/null"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rig::kernel_tests
