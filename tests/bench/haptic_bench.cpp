// bench-haptic: what one haptic servo tick costs (model force + mass-spring cornea), at the
// paper's mesh (13 x 13 = 169 vertices, 886 springs), at 10x and 100x its vertices, and the
// largest mesh whose median tick still fits the 1 ms servo period on one core. The baseline,
// measured in the same run, is the same tick with the mesh switched off.
//
//   ./rig bench haptic [--ticks N] [--repeats R] [--format json]
#include <sched.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <vector>

#include "force_model.hpp"
#include "model_force_source.hpp"
#include "servo_loop.hpp"

namespace {

using rig::haptic::ServoLoop;
using rig::haptic::ServoSettings;

struct TickCost {
  int n = 0;  // mesh vertices per side (0: no mesh)
  int vertices = 0, springs = 0;
  double p50_us = 0.0, p99_us = 0.0;
};

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

// One pass: the stylus pushed along the axis from 0.5 mm outside to 5 mm deep (past the
// puncture, so both the following and the cut mesh are timed). Returns each tick's cost [us].
std::vector<double> one_pass(ServoLoop& servo, int ticks) {
  std::vector<double> cost(static_cast<std::size_t>(ticks));
  for (int i = 0; i < ticks; ++i) {
    const double t = i * 0.001;
    const double depth = -0.5 + 5.5 * i / ticks;
    const auto start = std::chrono::steady_clock::now();
    const rig::drivers::Vec3 force = servo.tick({0.0, 0.0, -depth}, t);
    const auto end = std::chrono::steady_clock::now();
    asm volatile("" : : "g"(&force) : "memory");  // keep the result alive
    cost[static_cast<std::size_t>(i)] =
        std::chrono::duration<double, std::micro>(end - start).count();
  }
  return cost;
}

TickCost measure(int n, int ticks, int repeats) {
  const rig::model::ForceModel model = rig::model::ForceModel::paper_interpreted();
  const rig::haptic::ModelForceSource source(model, 15.0);
  ServoSettings settings;
  settings.surface_mm = rig::drivers::Vec3{0.0, 0.0, 0.0};
  settings.count_late_ticks = false;
  settings.mesh_enabled = n > 0;
  settings.mesh.n = std::max(n, 3);
  const rig::drivers::HapticLimits limits{3.3, 0.88, 1.0};
  std::vector<double> p50s, p99s;
  TickCost cost;
  for (int r = 0; r < repeats; ++r) {
    ServoLoop servo(settings, source, limits);
    const std::vector<double> c = one_pass(servo, ticks);
    p50s.push_back(percentile(c, 0.5));
    p99s.push_back(percentile(c, 0.99));
    cost.vertices = n > 0 ? servo.mesh().vertex_count() : 0;
    cost.springs = n > 0 ? servo.mesh().spring_count() : 0;
  }
  cost.n = n;
  cost.p50_us = percentile(p50s, 0.5);  // median over the repeats
  cost.p99_us = percentile(p99s, 0.5);
  return cost;
}

// The largest n whose median tick is under the budget [us] (cost grows with n^2).
TickCost largest_fitting(double budget_us, int ticks, int repeats) {
  int low = 13, high = 400;
  TickCost best = measure(low, ticks, repeats);
  while (high - low > 2) {
    const int mid = (low + high) / 2;
    const TickCost c = measure(mid, ticks, repeats);
    if (c.p50_us < budget_us)
      low = mid, best = c;
    else
      high = mid;
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("bench-haptic: servo tick cost with the mass-spring cornea");
  int ticks = 3000, repeats = 3;
  std::string format = "text";
  app.add_option("--ticks", ticks, "ticks per pass")->check(CLI::Range(200, 1000000));
  app.add_option("--repeats", repeats, "passes per mesh size (median taken)")
      ->check(CLI::Range(1, 50));
  app.add_option("--format", format)->check(CLI::IsMember({"text", "json"}));
  CLI11_PARSE(app, argc, argv);
  cpu_set_t one_core;  // "on one core": the servo thread is not spread over the machine
  CPU_ZERO(&one_core);
  CPU_SET(0, &one_core);
  if (sched_setaffinity(0, sizeof(one_core), &one_core) != 0)
    std::fprintf(stderr, "bench-haptic: could not pin to CPU 0\n");

  std::vector<TickCost> rows = {measure(0, ticks, repeats), measure(13, ticks, repeats),
                                measure(41, ticks, repeats), measure(130, ticks, repeats)};
  const TickCost fits = largest_fitting(1000.0, std::min(ticks, 1500), repeats);
  const char* labels[] = {"baseline: model, no mesh", "paper mesh (1x)", "10x vertices",
                          "100x vertices"};
  if (format == "json") {
    nlohmann::json out = nlohmann::json::array();
    for (std::size_t i = 0; i < rows.size(); ++i) {
      out.push_back({{"case", labels[i]},
                     {"n", rows[i].n},
                     {"vertices", rows[i].vertices},
                     {"springs", rows[i].springs},
                     {"tick_p50_us", rows[i].p50_us},
                     {"tick_p99_us", rows[i].p99_us}});
    }
    std::cout << nlohmann::json{{"ticks", out},
                                {"largest_n_under_1ms", fits.n},
                                {"largest_vertices", fits.vertices},
                                {"largest_springs", fits.springs},
                                {"largest_tick_p50_us", fits.p50_us}}
                     .dump(2)
              << "\n";
    return 0;
  }
  std::printf("servo tick cost, median of %d passes of %d ticks, pinned to CPU 0\n", repeats,
              ticks);
  std::printf("%-26s %5s %9s %9s %12s %12s\n", "case", "n", "vertices", "springs", "p50 [us]",
              "p99 [us]");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::printf("%-26s %5d %9d %9d %12.1f %12.1f\n", labels[i], rows[i].n, rows[i].vertices,
                rows[i].springs, rows[i].p50_us, rows[i].p99_us);
  }
  std::printf(
      "largest mesh with a median tick under 1 ms: n = %d (%d vertices, %d springs), p50 %.1f us\n",
      fits.n, fits.vertices, fits.springs, fits.p50_us);
  return 0;
}
