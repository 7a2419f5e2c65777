// The Aravis camera driver against Aravis's GigE Vision simulator: the arv-fake-gv-camera
// process on loopback (software trigger, polled at 25 Hz by the simulator), and the same
// simulator in-process for trigger rates above 25 Hz. Frames go to a per-run frame file
// with an index in the archive, each tied to the sample its trigger was raised at.
#include <arv.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <thread>

#include "archive.hpp"
#include "camera/aravis_camera.hpp"
#include "child_process.hpp"
#include "clock/monotonic_clock.hpp"
#include "frame_file.hpp"
#include "frame_sample_mapper.hpp"
#include "test_paths.hpp"

namespace rig {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t now_ns() {
  return static_cast<std::uint64_t>(drivers::MonotonicClock().now_ns());
}

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
std::unique_ptr<drivers::AravisCamera> open_when_ready(const std::string& id,
                                                       const drivers::CameraSettings& s) {
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

constexpr std::int64_t kFirstSample = 1000;  // loop cycle of the first trigger

// One software trigger: the loop cycle it stands for, when the host raised it and when the
// camera acknowledged the command [ns, CLOCK_MONOTONIC]. The camera received it in between.
struct TriggerRecord {
  std::int64_t sample = 0;
  std::uint64_t raised_ns = 0;
  std::uint64_t acknowledged_ns = 0;
};

// One complete frame the camera delivered, whether the mapper tied it or not.
struct FrameRecord {
  std::uint64_t frame_id = 0;
  std::uint64_t camera_ns = 0;   // the camera's exposure timestamp [ns, the camera's clock]
  std::uint64_t arrival_ns = 0;  // [ns, CLOCK_MONOTONIC]
  std::optional<std::int64_t> sample;
};

struct Recorded {
  std::vector<TriggerRecord> triggers;
  std::vector<FrameRecord> frames;    // every complete frame delivered, in order
  std::vector<std::int64_t> samples;  // the tied frames' samples, in order: one index row each
  std::vector<double> latency_ms;
  std::uint64_t checksum_of_frame_10 = 0;
  std::uint64_t incomplete = 0;           // frames delivered with missing packets (not in `frames`)
  std::uint64_t incomplete_at_start = 0;  // of them, before the first complete frame
  std::uint64_t lost = 0;    // triggers the mapper reports unanswered, once the run is over
  std::uint64_t untied = 0;  // frames with no trigger to tie them to
};

// Where a run's tied frames go: its frame file and the archive's index.
struct RunFiles {
  archive::Archive& archive;
  std::int64_t run_id;
  archive::FrameFile& file;
};

// Raises one software trigger per `period`, trigger k standing for sample kFirstSample +
// k * samples_per_trigger (the loop runs at 1 kHz), and tells the mapper.
void fire_triggers(drivers::Camera& camera, archive::FrameSampleMapper& mapper,
                   std::chrono::microseconds period, std::vector<TriggerRecord>& triggers) {
  const std::int64_t samples_per_trigger = period.count() / 1000;
  const auto start = Clock::now();
  for (int k = 0; k < static_cast<int>(triggers.size()); ++k) {
    TriggerRecord& t = triggers[static_cast<std::size_t>(k)];
    t.sample = kFirstSample + k * samples_per_trigger;
    t.raised_ns = now_ns();
    mapper.on_trigger(t.sample, t.raised_ns);
    camera.trigger_software();  // returns once the camera acknowledged the command
    t.acknowledged_ns = now_ns();
    mapper.on_trigger_acknowledged(t.sample, t.acknowledged_ns);
    std::this_thread::sleep_until(start + period * (k + 1));
  }
}

// Ties one delivered frame through the mapper; a tied frame goes to the run's file and index.
void record_frame(const drivers::FrameView& frame, archive::FrameSampleMapper& mapper,
                  RunFiles& run, Recorded& r) {
  const std::optional<std::int64_t> sample =
      mapper.on_frame(frame.frame_id, frame.camera_timestamp_ns, frame.host_timestamp_ns);
  r.frames.push_back({frame.frame_id, frame.camera_timestamp_ns, frame.host_timestamp_ns, sample});
  if (!sample) return;
  const std::int64_t offset = run.file.append(frame.pixels);
  archive::FrameRow row{run.run_id,
                        static_cast<std::int64_t>(r.samples.size()),
                        *sample,
                        static_cast<std::int64_t>(frame.camera_timestamp_ns),
                        static_cast<std::int64_t>(frame.host_timestamp_ns),
                        offset,
                        static_cast<std::int64_t>(frame.pixels.size()),
                        frame.width,
                        frame.height,
                        run.file.path()};
  run.archive.add_frame(row);
  if (r.samples.size() == 10)
    r.checksum_of_frame_10 =
        std::accumulate(frame.pixels.begin(), frame.pixels.end(), std::uint64_t{0});
  r.samples.push_back(*sample);
  r.latency_ms.push_back(static_cast<double>(mapper.last_latency_ns()) * 1e-6);
}

// Fires `count` software triggers every `period` while recording the frames into the run's
// file and the archive's index.
Recorded record_triggered(drivers::Camera& camera, int count, std::chrono::microseconds period,
                          RunFiles run) {
  archive::FrameSampleMapper mapper;
  Recorded r;
  r.triggers.resize(
      static_cast<std::size_t>(count));  // written by the trigger thread, read after it joined
  EXPECT_EQ(camera.start(), drivers::IoStatus::kOk);
  std::thread trigger([&] { fire_triggers(camera, mapper, period, r.triggers); });
  const auto end = Clock::now() + period * count + std::chrono::seconds(3);
  while (static_cast<int>(r.samples.size()) < count && Clock::now() < end) {
    drivers::FrameView frame;
    const drivers::IoStatus status = camera.next_frame(frame, 200000);
    if (status == drivers::IoStatus::kOk) record_frame(frame, mapper, run, r);
    if (status == drivers::IoStatus::kBadData) {
      ++r.incomplete;
      if (r.frames.empty()) ++r.incomplete_at_start;
    }
  }
  trigger.join();
  camera.stop();
  run.file.flush();
  mapper.count_unanswered_triggers_as_lost();  // no more frames will be read
  r.lost = mapper.lost_frames();
  r.untied = mapper.untied_frames();
  return r;
}

// Every frame carries the sample of its own trigger: sample = 1000 + k * step for some k,
// strictly increasing; with no frame lost, exactly k = 0, 1, 2, ...
void expect_tied_to_their_triggers(const Recorded& r, int count, std::int64_t samples_per_trigger) {
  ASSERT_LE(r.samples.size() + r.lost, static_cast<std::size_t>(count));
  for (std::size_t k = 0; k < r.samples.size(); ++k) {
    EXPECT_EQ((r.samples[k] - kFirstSample) % samples_per_trigger, 0) << "frame " << k;
    if (k > 0) {
      EXPECT_GT(r.samples[k], r.samples[k - 1]) << "frame " << k;
    }
  }
  if (r.lost == 0) {
    for (std::size_t k = 0; k < r.samples.size(); ++k)
      EXPECT_EQ(r.samples[k], kFirstSample + static_cast<std::int64_t>(k) * samples_per_trigger);
  }
}

// ---- What the fake camera's own frames show -------------------------------------------------
// arv-fake-gv-camera's acquisition thread polls its trigger register every 40 ms (25 Hz, on the
// wall clock). A software trigger sets the register; the first poll after that exposes a frame,
// stamps it with g_get_real_time() of this machine (CLOCK_REALTIME, µs) and clears the register.
// So each delivered frame marks one poll, and a poll that found a trigger always made a frame.
// Two triggers that reach the camera with no poll between them give one frame: on a quiet
// machine that cannot happen at 10 Hz, but a starved acquisition thread (or a stalled trigger
// thread) lets it happen, and only the frames' timestamps and ids can show it.

// CLOCK_REALTIME - CLOCK_MONOTONIC [ns]: the fake camera's timestamps on the host's
// monotonic clock, to a few µs, without the mapper's own estimate.
std::int64_t realtime_minus_monotonic_ns() {
  timespec real{}, mono{};
  clock_gettime(CLOCK_REALTIME, &real);
  clock_gettime(CLOCK_MONOTONIC, &mono);
  return (static_cast<std::int64_t>(real.tv_sec) - mono.tv_sec) * 1'000'000'000 +
         (real.tv_nsec - mono.tv_nsec);
}

// Each delivered frame's exposure on CLOCK_MONOTONIC [ns].
std::vector<std::int64_t> exposures_on_host_clock(const Recorded& r) {
  const std::int64_t shift_ns = realtime_minus_monotonic_ns();
  std::vector<std::int64_t> exposed;
  for (const FrameRecord& f : r.frames) {
    exposed.push_back(static_cast<std::int64_t>(f.camera_ns) - shift_ns);
    const std::int64_t transfer_ns = static_cast<std::int64_t>(f.arrival_ns) - exposed.back();
    EXPECT_TRUE(transfer_ns >= 0 && transfer_ns < 1'000'000'000)
        << "frame id " << f.frame_id << " arrived " << transfer_ns
        << " ns after its exposure: the fake camera no longer stamps "
        << "frames with this machine's CLOCK_REALTIME, and this test's reading of its timestamps "
           "is wrong";
  }
  return exposed;
}

// The fake camera numbers frames 1..65535 and skips 0.
bool follows(std::uint64_t frame_id, std::uint64_t previous_id) {
  return frame_id == (previous_id >= 65535 ? 1 : previous_id + 1);
}

double ms_after_first_trigger(const Recorded& r, std::int64_t host_ns) {
  return static_cast<double>(host_ns - static_cast<std::int64_t>(r.triggers.front().raised_ns)) *
         1e-6;
}

// Triggers (indices) that may have been waiting at the poll that exposed frame f: raised
// before its exposure, and not certainly at the camera before the previous frame's exposure
// (a trigger it held then was answered by that poll or an earlier one). The frame answers
// these, one or (merged) several.
std::vector<std::size_t> triggers_possibly_waiting_at(const Recorded& r,
                                                      const std::vector<std::int64_t>& exposed,
                                                      std::size_t f) {
  std::vector<std::size_t> waiting;
  for (std::size_t k = 0; k < r.triggers.size(); ++k) {
    const bool raised_before = static_cast<std::int64_t>(r.triggers[k].raised_ns) <= exposed[f];
    const bool held_at_previous_poll =
        f > 0 && static_cast<std::int64_t>(r.triggers[k].acknowledged_ns) <= exposed[f - 1];
    if (raised_before && !held_at_previous_poll) waiting.push_back(k);
  }
  return waiting;
}

// Every delivered frame is tied, to a trigger its poll may have held, each trigger once.
void expect_each_frame_tied_to_a_trigger_it_may_answer(const Recorded& r,
                                                       const std::vector<std::int64_t>& exposed) {
  std::int64_t previous_sample = kFirstSample - 1;
  for (std::size_t f = 0; f < r.frames.size(); ++f) {
    const FrameRecord& frame = r.frames[f];
    const std::string where = "frame id " + std::to_string(frame.frame_id) + " exposed at " +
                              std::to_string(ms_after_first_trigger(r, exposed[f])) +
                              " ms after the first trigger";
    ASSERT_TRUE(frame.sample.has_value()) << where << ": not tied to a sample";
    std::string allowed_samples;
    bool allowed = false;
    for (const std::size_t k : triggers_possibly_waiting_at(r, exposed, f)) {
      allowed = allowed || r.triggers[k].sample == *frame.sample;
      allowed_samples += " " + std::to_string(r.triggers[k].sample);
    }
    EXPECT_TRUE(allowed) << where << " is tied to sample " << *frame.sample
                         << "; by its timestamp it may answer only samples:" << allowed_samples;
    EXPECT_GT(*frame.sample, previous_sample)
        << where << ": tied to a sample already answered or older";
    previous_sample = *frame.sample;
  }
}

// The triggers no frame was tied to, and how many of them the camera's frames excuse. A poll
// that found n triggers waiting made one frame for them: n - 1 may go unanswered. That needs
// two triggers between two consecutive polls (frame timestamps): the gap between the frames
// spans the whole spacing of the triggers, so the loop did not poll between the first one's
// acknowledgement and the second one's raise. On a quiet machine the loop polls every 40 ms
// and triggers come every 100 ms, so it never does. The polls are all seen only while no frame
// id is skipped: a frame lost on its way is not a merge and excuses nothing.
struct Losses {
  std::vector<std::size_t> unanswered;  // indices into r.triggers
  std::size_t excused = 0;
};

Losses losses_the_camera_excuses(const Recorded& r, const std::vector<std::int64_t>& exposed) {
  Losses losses;
  constexpr std::size_t kNoFrame = ~std::size_t{0};
  std::vector<std::size_t> answering_frame(r.triggers.size(), kNoFrame);
  for (std::size_t f = 0; f < r.frames.size(); ++f) {
    for (std::size_t k = 0; k < r.triggers.size(); ++k) {
      if (r.frames[f].sample == r.triggers[k].sample) answering_frame[k] = f;
    }
  }
  for (std::size_t k = 0; k < r.triggers.size(); ++k) {
    if (answering_frame[k] == kNoFrame) losses.unanswered.push_back(k);
  }
  std::vector<bool> excused(r.triggers.size(), false);
  for (std::size_t f = 0; f < r.frames.size(); ++f) {
    if (f > 0 && !follows(r.frames[f].frame_id, r.frames[f - 1].frame_id)) continue;
    std::vector<std::size_t> merged;  // waiting at this poll and answered by no other frame
    for (const std::size_t k : triggers_possibly_waiting_at(r, exposed, f)) {
      if (answering_frame[k] == kNoFrame || answering_frame[k] == f) merged.push_back(k);
    }
    std::size_t may_go_unanswered = merged.empty() ? 0 : merged.size() - 1;
    for (const std::size_t k : merged) {
      if (answering_frame[k] != kNoFrame || excused[k] || may_go_unanswered == 0) continue;
      excused[k] = true;
      --may_go_unanswered;
      ++losses.excused;
    }
  }
  return losses;
}

// Prints what the camera showed around each unanswered trigger, so a failure explains itself.
void print_unanswered(const Recorded& r, const std::vector<std::int64_t>& exposed,
                      const Losses& losses) {
  for (const std::size_t k : losses.unanswered) {
    const TriggerRecord& t = r.triggers[k];
    std::printf(
        "  trigger %zu (sample %lld) raised at %.1f ms, acknowledged at %.1f ms; frames exposed "
        "around it [ms]:",
        k, static_cast<long long>(t.sample),
        ms_after_first_trigger(r, static_cast<std::int64_t>(t.raised_ns)),
        ms_after_first_trigger(r, static_cast<std::int64_t>(t.acknowledged_ns)));
    for (std::size_t f = 0; f < r.frames.size(); ++f) {
      const double at_ms = ms_after_first_trigger(r, exposed[f]);
      const double raised_ms = ms_after_first_trigger(r, static_cast<std::int64_t>(t.raised_ns));
      if (std::abs(at_ms - raised_ms) < 300.0)
        std::printf(" %.1f (id %llu)", at_ms,
                    static_cast<unsigned long long>(r.frames[f].frame_id));
    }
    std::printf("\n");
  }
}

// Every frame id follows the previous one: the camera delivered every frame it made.
void expect_no_frame_id_skipped(const Recorded& r) {
  for (std::size_t f = 1; f < r.frames.size(); ++f) {
    EXPECT_TRUE(follows(r.frames[f].frame_id, r.frames[f - 1].frame_id))
        << "frame id " << r.frames[f].frame_id << " after " << r.frames[f - 1].frame_id
        << ": a frame the camera made never arrived";
  }
}

void expect_index_and_pixels_match_the_recorded_frames(const Recorded& r, archive::Archive& archive,
                                                       std::int64_t run_id,
                                                       const std::filesystem::path& frame_file) {
  const std::vector<archive::FrameRow> index = archive.run_frames(run_id);
  ASSERT_EQ(index.size(), r.samples.size());
  ASSERT_GT(index.size(), 10U);
  std::int64_t expected_offset = 16;  // after the file header [B]
  for (std::size_t k = 0; k < index.size(); ++k) {
    EXPECT_EQ(index[k].sample_index, r.samples[k]);
    EXPECT_EQ(index[k].file_offset, expected_offset);
    EXPECT_EQ(index[k].width, 320);
    EXPECT_EQ(index[k].bytes, 320 * 240);
    expected_offset += index[k].bytes;
  }
  EXPECT_EQ(static_cast<std::int64_t>(std::filesystem::file_size(frame_file)), expected_offset);
  // The pixels come back from the file where the index says.
  std::ifstream in(frame_file, std::ios::binary);
  std::vector<char> pixels(static_cast<std::size_t>(index[10].bytes));
  in.seekg(index[10].file_offset);
  in.read(pixels.data(), static_cast<std::streamsize>(pixels.size()));
  std::uint64_t checksum = 0;
  for (const char c : pixels) checksum += static_cast<std::uint8_t>(c);
  EXPECT_EQ(checksum, r.checksum_of_frame_10);
}

TEST(AravisCamera, FiftySoftwareTriggeredFramesFromTheFakeGigECameraAreEachTiedToTheirSample) {
  testing::ScratchDir dir("aravis-gv");
  cli::ChildProcess simulator({"/usr/bin/arv-fake-gv-camera-0.8", "-i", "127.0.0.1"},
                              dir.file("fake-camera.log"));
  const auto camera = open_when_ready("127.0.0.1", triggered_settings());
  archive::Archive archive(dir.file("archive.sqlite"));
  const std::int64_t run_id = archive.create_run(archive::NewRun{"CAM01"});
  archive::FrameFile file(dir.file("run-" + std::to_string(run_id) + ".frames"));
  // 10 Hz: the simulator polls its software trigger at 25 Hz, so one trigger per poll window.
  const Recorded r = record_triggered(*camera, 50, std::chrono::milliseconds(100),
                                      RunFiles{archive, run_id, file});
  const std::vector<std::int64_t> exposed = exposures_on_host_clock(r);
  expect_each_frame_tied_to_a_trigger_it_may_answer(r, exposed);
  expect_no_frame_id_skipped(r);
  EXPECT_EQ(r.untied, 0U) << "no frame without its trigger";
  // The fake camera's stream can open with frames missing packets (docs/camera.md; under
  // ./rig stress 1 to 3 of them, every trigger still answered). After the first complete frame
  // none may come incomplete on loopback.
  EXPECT_EQ(r.incomplete, r.incomplete_at_start)
      << "frames with missing packets on loopback, after the stream's first";
  std::printf("incomplete frames: %llu, all before the first complete one: %s\n",
              static_cast<unsigned long long>(r.incomplete),
              r.incomplete == r.incomplete_at_start ? "yes" : "no");
  const Losses losses = losses_the_camera_excuses(r, exposed);
  EXPECT_EQ(r.lost, losses.unanswered.size())
      << "the mapper reports every trigger no frame answered";
  EXPECT_EQ(losses.excused, losses.unanswered.size())
      << "a trigger may go unanswered only if the camera's own frames show "
         "that it and another one waited for the same poll";
  print_unanswered(r, exposed, losses);
  expect_index_and_pixels_match_the_recorded_frames(r, archive, run_id, file.path());
  std::vector<double> sorted = r.latency_ms;
  std::sort(sorted.begin(), sorted.end());
  std::printf(
      "fake GigE camera, 10 Hz software trigger: %zu of 50 triggers answered, %zu unanswered, %zu "
      "of them excused by "
      "the camera's timestamps; latency p50 %.1f ms, max %.1f ms (the simulator polls at 25 Hz)\n",
      r.samples.size(), losses.unanswered.size(), losses.excused, sorted[sorted.size() / 2],
      sorted.back());
  EXPECT_GE(camera->counters().frames, r.samples.size());
}

struct InProcessFakeCamera {
  ArvGvFakeCamera* camera = nullptr;
  explicit InProcessFakeCamera(double trigger_check_hz) {
    camera = arv_gv_fake_camera_new("127.0.0.1", "GV09");
    if (camera != nullptr)
      arv_fake_camera_set_trigger_frequency(arv_gv_fake_camera_get_fake_camera(camera),
                                            trigger_check_hz);
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
  const Recorded r = record_triggered(*camera, 100, std::chrono::milliseconds(10),
                                      RunFiles{archive, run_id, file});
  expect_tied_to_their_triggers(r, 100, 10);
  // Every frame kept is tied to its own trigger (above) whatever the load. How many of the 100
  // triggers Aravis's simulator answers is a rate figure (bench-camera prints it): its trigger
  // thread runs late on a loaded machine and merges triggers (measured under ./rig stress:
  // 50 tied, 7 untied). Bounds here only say that it works at this rate at all, and that a
  // merged trigger is counted, never tied to the wrong sample.
  EXPECT_GE(r.samples.size(), 25U);
  EXPECT_LE(r.untied, r.samples.size() / 4);
  EXPECT_EQ(archive.run_frames(run_id).size(), r.samples.size());
  std::printf(
      "in-process simulator, 100 Hz trigger: %zu frames tied, %llu triggers unanswered, %llu "
      "frames untied\n",
      r.samples.size(), static_cast<unsigned long long>(r.lost),
      static_cast<unsigned long long>(r.untied));
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
