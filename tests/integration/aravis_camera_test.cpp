// The Aravis camera driver against Aravis's GigE Vision simulator: the arv-fake-gv-camera
// process on loopback (software trigger, polled at 25 Hz by the simulator), and the same
// simulator in-process for trigger rates above 25 Hz. Frames go to a per-run frame file
// with an index in the archive, each tied to the sample its trigger was raised at.
#include <arv.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <thread>

#include "archive.hpp"
#include "camera/aravis_camera.hpp"
#include "clock/monotonic_clock.hpp"
#include "child_process.hpp"
#include "frame_file.hpp"
#include "frame_sample_mapper.hpp"
#include "test_paths.hpp"

namespace rig {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t now_ns() { return static_cast<std::uint64_t>(drivers::MonotonicClock().now_ns()); }

drivers::CameraSettings triggered_settings() {
  drivers::CameraSettings s;
  s.width = 320;
  s.height = 240;
  s.exposure_us = 1000.0;
  s.frame_rate_hz = 200.0;
  s.software_trigger = true;
  s.packet_size = 1400;
  s.buffer_count = 32;
  return s;
}

// The simulator needs a moment to listen (and a killed client holds it for 3 s).
std::unique_ptr<drivers::AravisCamera> open_when_ready(const std::string& id, const drivers::CameraSettings& s) {
  std::string last_error;
  for (const auto end = Clock::now() + std::chrono::seconds(8); Clock::now() < end;) {
    try {
      return std::make_unique<drivers::AravisCamera>(id, s);
    } catch (const std::runtime_error& e) {
      last_error = e.what();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  throw std::runtime_error("the camera simulator did not come up: " + last_error);
}

struct Recorded {
  std::vector<std::int64_t> samples;
  std::vector<std::uint64_t> frame_ids;
  std::vector<double> latency_ms;
  std::uint64_t checksum_of_frame_10 = 0;
  std::uint64_t lost = 0;    // triggers the camera answered with no frame
  std::uint64_t untied = 0;  // frames with no trigger to tie them to
  // Triggers raised less than one poll window of the fake camera (40 ms) after the previous
  // one was acknowledged: only then may the camera merge two into one frame. A quiet
  // machine raises every 100 ms; a stalled trigger thread catches up in a burst.
  std::uint64_t crowded = 0;
};

// Fires `count` software triggers every `period` (a trigger at sample 1000 + k * samples_per
// trigger) while recording the frames into the run's file and the archive's index.
Recorded record_triggered(drivers::Camera& camera, int count, std::chrono::microseconds period, archive::Archive& archive,
                          std::int64_t run_id, archive::FrameFile& file) {
  archive::FrameSampleMapper mapper;
  Recorded r;
  const std::int64_t samples_per_trigger = period.count() / 1000;  // loop at 1 kHz
  EXPECT_EQ(camera.start(), drivers::IoStatus::kOk);
  std::thread trigger([&] {
    const auto start = Clock::now();
    std::uint64_t previous_ack_ns = 0;
    constexpr std::uint64_t kPollWindow_ns = 40'000'000;  // the fake camera polls at 25 Hz
    for (int k = 0; k < count; ++k) {
      const std::int64_t sample = 1000 + k * samples_per_trigger;
      const std::uint64_t raised_ns = now_ns();
      if (k > 0 && raised_ns - previous_ack_ns < kPollWindow_ns) ++r.crowded;
      mapper.on_trigger(sample, raised_ns);
      camera.trigger_software();  // returns once the camera acknowledged the command
      previous_ack_ns = now_ns();
      mapper.on_trigger_acknowledged(sample, previous_ack_ns);
      std::this_thread::sleep_until(start + period * (k + 1));
    }
  });
  const auto end = Clock::now() + period * count + std::chrono::seconds(3);
  while (static_cast<int>(r.samples.size()) < count && Clock::now() < end) {
    drivers::FrameView frame;
    if (camera.next_frame(frame, 200000) != drivers::IoStatus::kOk) continue;
    const std::optional<std::int64_t> sample = mapper.on_frame(frame.frame_id, frame.camera_timestamp_ns, frame.host_timestamp_ns);
    if (!sample) continue;
    const std::int64_t offset = file.append(frame.pixels);
    archive::FrameRow row{run_id, static_cast<std::int64_t>(r.samples.size()), *sample,
                          static_cast<std::int64_t>(frame.camera_timestamp_ns), static_cast<std::int64_t>(frame.host_timestamp_ns),
                          offset, static_cast<std::int64_t>(frame.pixels.size()), frame.width, frame.height, file.path()};
    archive.add_frame(row);
    if (r.samples.size() == 10) r.checksum_of_frame_10 = std::accumulate(frame.pixels.begin(), frame.pixels.end(), std::uint64_t{0});
    r.samples.push_back(*sample);
    r.frame_ids.push_back(frame.frame_id);
    r.latency_ms.push_back(static_cast<double>(mapper.last_latency_ns()) * 1e-6);
  }
  trigger.join();
  camera.stop();
  file.flush();
  r.lost = mapper.lost_frames();
  r.untied = mapper.untied_frames();
  return r;
}

// Every frame carries the sample of its own trigger: sample = 1000 + k * step for some k,
// strictly increasing; with no frame lost, exactly k = 0, 1, 2, ...
void expect_tied_to_their_triggers(const Recorded& r, int count, std::int64_t samples_per_trigger) {
  ASSERT_LE(r.samples.size() + r.lost, static_cast<std::size_t>(count));
  for (std::size_t k = 0; k < r.samples.size(); ++k) {
    EXPECT_EQ((r.samples[k] - 1000) % samples_per_trigger, 0) << "frame " << k;
    if (k > 0) {
      EXPECT_GT(r.samples[k], r.samples[k - 1]) << "frame " << k;
    }
  }
  if (r.lost == 0) {
    for (std::size_t k = 0; k < r.samples.size(); ++k) EXPECT_EQ(r.samples[k], 1000 + static_cast<std::int64_t>(k) * samples_per_trigger);
  }
}

TEST(AravisCamera, FiftySoftwareTriggeredFramesFromTheFakeGigECameraAreEachTiedToTheirSample) {
  testing::ScratchDir dir("aravis-gv");
  cli::ChildProcess simulator({"/usr/bin/arv-fake-gv-camera-0.8", "-i", "127.0.0.1"}, dir.file("fake-camera.log"));
  const auto camera = open_when_ready("127.0.0.1", triggered_settings());
  archive::Archive archive(dir.file("archive.sqlite"));
  const std::int64_t run_id = archive.create_run(archive::NewRun{"CAM01"});
  archive::FrameFile file(dir.file("run-" + std::to_string(run_id) + ".frames"));
  // 10 Hz: the simulator polls its software trigger at 25 Hz, so one trigger per poll window.
  const Recorded r = record_triggered(*camera, 50, std::chrono::milliseconds(100), archive, run_id, file);
  expect_tied_to_their_triggers(r, 50, 100);
  // One trigger per poll window: the simulator answers every one, unless the machine stalled
  // the trigger thread so that it raised two in one window (counted, never the case idle).
  EXPECT_LE(r.lost, r.crowded) << "one trigger per poll window: the simulator answers every one";
  EXPECT_GE(r.samples.size() + r.crowded, 50U) << "only a crowded trigger may go unanswered";
  EXPECT_EQ(r.untied, 0U) << "no frame without its trigger";
  const std::vector<archive::FrameRow> index = archive.run_frames(run_id);
  ASSERT_EQ(index.size(), r.samples.size());
  std::int64_t expected_offset = 16;  // after the file header
  for (std::size_t k = 0; k < index.size(); ++k) {
    EXPECT_EQ(index[k].sample_index, r.samples[k]);
    EXPECT_EQ(index[k].file_offset, expected_offset);
    EXPECT_EQ(index[k].width, 320);
    EXPECT_EQ(index[k].bytes, 320 * 240);
    expected_offset += index[k].bytes;
  }
  EXPECT_EQ(static_cast<std::int64_t>(std::filesystem::file_size(file.path())), expected_offset);
  // The pixels come back from the file where the index says.
  std::ifstream in(file.path(), std::ios::binary);
  std::vector<char> pixels(static_cast<std::size_t>(index[10].bytes));
  in.seekg(index[10].file_offset);
  in.read(pixels.data(), static_cast<std::streamsize>(pixels.size()));
  std::uint64_t checksum = 0;
  for (const char c : pixels) checksum += static_cast<std::uint8_t>(c);
  EXPECT_EQ(checksum, r.checksum_of_frame_10);
  std::vector<double> sorted = r.latency_ms;
  std::sort(sorted.begin(), sorted.end());
  std::printf("fake GigE camera, 10 Hz software trigger: latency p50 %.1f ms, max %.1f ms (the simulator polls at 25 Hz)\n",
              sorted[sorted.size() / 2], sorted.back());
  EXPECT_GE(camera->counters().frames, r.samples.size());
}

struct InProcessFakeCamera {
  ArvGvFakeCamera* camera = nullptr;
  explicit InProcessFakeCamera(double trigger_check_hz) {
    camera = arv_gv_fake_camera_new("127.0.0.1", "GV09");
    if (camera != nullptr) arv_fake_camera_set_trigger_frequency(arv_gv_fake_camera_get_fake_camera(camera), trigger_check_hz);
  }
  ~InProcessFakeCamera() {
    if (camera != nullptr) g_object_unref(camera);
  }
};

TEST(AravisCamera, TheInProcessSimulatorTakesA100HzTriggerAndTiesItsFramesToTheirOwnTriggers) {
  testing::ScratchDir dir("aravis-fast");
  InProcessFakeCamera simulator(1000.0);
  ASSERT_NE(simulator.camera, nullptr);
  ASSERT_TRUE(arv_gv_fake_camera_is_running(simulator.camera));
  const auto camera = open_when_ready("127.0.0.1", triggered_settings());
  archive::Archive archive(dir.file("archive.sqlite"));
  const std::int64_t run_id = archive.create_run(archive::NewRun{"CAM02"});
  archive::FrameFile file(dir.file("run.frames"));
  const Recorded r = record_triggered(*camera, 100, std::chrono::milliseconds(10), archive, run_id, file);
  expect_tied_to_their_triggers(r, 100, 10);
  // Every frame kept is tied to its own trigger (above) whatever the load. How many of the 100
  // triggers Aravis's simulator answers is a rate figure (bench-camera prints it): its trigger
  // thread runs late on a loaded machine and merges triggers (measured under ./rig stress:
  // 50 tied, 7 untied). Bounds here only say that it works at this rate at all, and that a
  // merged trigger is counted, never tied to the wrong sample.
  EXPECT_GE(r.samples.size(), 25U);
  EXPECT_LE(r.untied, r.samples.size() / 4);
  EXPECT_EQ(archive.run_frames(run_id).size(), r.samples.size());
  std::printf("in-process simulator, 100 Hz trigger: %zu frames tied, %llu triggers unanswered, %llu frames untied\n",
              r.samples.size(), static_cast<unsigned long long>(r.lost), static_cast<unsigned long long>(r.untied));
  const drivers::CameraCounters c = camera->counters();
  EXPECT_EQ(c.missing_packets, 0U);
}

TEST(AravisCamera, ACameraThatIsNotThereIsAClearErrorNamingIt) {
  try {
    drivers::AravisCamera camera("Nowhere-CAM-404", triggered_settings());
    FAIL() << "opened a camera that does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("Nowhere-CAM-404"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rig
