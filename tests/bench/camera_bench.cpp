// bench-camera: trigger-to-frame latency and lost frames against Aravis's GigE Vision
// simulator running in this process on loopback (its trigger checked at 1 kHz), at rising
// software-trigger rates; each frame is tied to its trigger as rigd ties it to a sample.
//
//   ./rig bench camera [--seconds S] [--rates 25,50,100,200,400]
#include <arv.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "camera/aravis_camera.hpp"
#include "clock/monotonic_clock.hpp"
#include "frame_sample_mapper.hpp"

namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t now_ns() {
  return static_cast<std::uint64_t>(rig::drivers::MonotonicClock().now_ns());
}

struct RateResult {
  double rate_hz = 0.0;
  int triggers = 0, frames = 0;
  std::uint64_t lost = 0, untied = 0, missing_packets = 0;
  double p50_ms = 0.0, p99_ms = 0.0;
};

RateResult run_rate(double rate_hz, double seconds) {
  rig::drivers::CameraSettings s;
  s.width = 320;
  s.height = 240;
  s.exposure_us = 500.0;
  s.frame_rate_hz = 1000.0;
  s.software_trigger = true;
  s.buffer_count = 64;
  rig::drivers::AravisCamera camera("127.0.0.1", s);
  rig::archive::FrameSampleMapper mapper;
  RateResult r;
  r.rate_hz = rate_hz;
  r.triggers = static_cast<int>(rate_hz * seconds);
  const auto period = std::chrono::duration<double>(1.0 / rate_hz);
  std::vector<double> latency_ms;
  camera.start();
  std::thread trigger([&] {
    const auto start = Clock::now();
    for (int k = 0; k < r.triggers; ++k) {
      mapper.on_trigger(k, now_ns());
      camera.trigger_software();
      std::this_thread::sleep_until(start +
                                    std::chrono::duration_cast<Clock::duration>(period * (k + 1)));
    }
  });
  const auto end = Clock::now() + std::chrono::duration<double>(seconds + 1.0);
  while (Clock::now() < end) {
    rig::drivers::FrameView frame;
    if (camera.next_frame(frame, 100000) != rig::drivers::IoStatus::kOk) continue;
    if (mapper.on_frame(frame.frame_id, frame.camera_timestamp_ns, frame.host_timestamp_ns)) {
      ++r.frames;
      latency_ms.push_back(static_cast<double>(mapper.last_latency_ns()) * 1e-6);
    }
  }
  trigger.join();
  camera.stop();
  r.lost = static_cast<std::uint64_t>(r.triggers - r.frames);
  r.untied = mapper.untied_frames();
  r.missing_packets = camera.counters().missing_packets;
  std::sort(latency_ms.begin(), latency_ms.end());
  if (!latency_ms.empty()) {
    r.p50_ms = latency_ms[latency_ms.size() / 2];
    r.p99_ms =
        latency_ms[static_cast<std::size_t>(0.99 * static_cast<double>(latency_ms.size() - 1))];
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("bench-camera: trigger-to-frame latency and lost frames on Aravis's simulator");
  double seconds = 3.0;
  std::vector<double> rates = {25, 50, 100, 200, 400};
  app.add_option("--seconds", seconds, "seconds per rate")->check(CLI::Range(0.5, 60.0));
  app.add_option("--rates", rates, "software trigger rates [Hz]")->delimiter(',');
  CLI11_PARSE(app, argc, argv);
  ArvGvFakeCamera* simulator = arv_gv_fake_camera_new("127.0.0.1", "GV09");
  if (simulator == nullptr || !arv_gv_fake_camera_is_running(simulator)) {
    std::fprintf(
        stderr,
        "bench-camera: cannot start the simulator on 127.0.0.1:3956 (another one running?)\n");
    return 1;
  }
  arv_fake_camera_set_trigger_frequency(arv_gv_fake_camera_get_fake_camera(simulator), 1000.0);
  std::printf(
      "software trigger -> frame, 320x240 Mono8, in-process GigE Vision simulator, %.1f s per "
      "rate\n",
      seconds);
  std::printf("%10s %9s %7s %7s %11s %13s %13s\n", "rate [Hz]", "triggers", "frames", "lost",
              "lost [%]", "latency p50", "latency p99");
  for (const double rate : rates) {
    const RateResult r = run_rate(rate, seconds);
    std::printf("%10.0f %9d %7d %7llu %10.1f%% %10.2f ms %10.2f ms\n", r.rate_hz, r.triggers,
                r.frames, static_cast<unsigned long long>(r.lost),
                100.0 * static_cast<double>(r.lost) / r.triggers, r.p50_ms, r.p99_ms);
  }
  g_object_unref(simulator);
  return 0;
}
