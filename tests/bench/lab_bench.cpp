// bench-lab: diagnose 100 simulated runs of ~14,000 samples (the benchmark) and
// print the whole-process time and where it went.
//   bench-lab [--runs 100] [--threads 2] [--effect shaft_friction]
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

#include "diagnosis.hpp"
#include "run_generator.hpp"

int main(int argc, char** argv) {
  const auto process_start = std::chrono::steady_clock::now();
  CLI::App app{"bench-lab: model lab diagnosis on many simulated runs"};
  int runs = 100;
  int threads = 2;
  std::string effect = "shaft_friction";
  app.add_option("--runs", runs, "number of runs");
  app.add_option("--threads", threads, "worker threads for the candidates");
  app.add_option("--effect", effect, "hidden effect (empty: clean)");
  CLI11_PARSE(app, argc, argv);
  rig::sim::GeneratorOptions g;
  if (!effect.empty()) {
    std::string error;
    g.effects.push_back(*rig::sim::parse_hidden_effect(effect, error));
  }
  std::vector<rig::model::RunData> data;
  std::size_t samples = 0;
  // 14 mm at 1-3 mm/s with approach and retraction: ~14,000 samples on average.
  const auto specs = rig::sim::design_runs({15, 16, 17, 18, 15.5}, {1, 1.5, 2, 2.5, 3}, {0.5, 1.5, 2.5, 3.5}, 14.0, 0.0, 9);
  for (int i = 0; i < runs; ++i) {
    rig::sim::RunSpec spec = specs[static_cast<std::size_t>(i) % specs.size()];
    spec.seed += static_cast<std::uint64_t>(i) * 7919;
    spec.eye_id += "-" + std::to_string(i);
    data.push_back(rig::sim::generate_run(g, spec));
    samples += data.back().size();
  }
  const auto generated = std::chrono::steady_clock::now();
  rig::model::DiagnoseOptions options;
  options.threads = threads;
  const rig::model::Diagnosis d = rig::model::diagnose(rig::model::ForceModel::paper_interpreted(), data, options);
  const auto done = std::chrono::steady_clock::now();
  auto s = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::printf("runs %d, samples %zu (%.0f per run)\n", runs, samples, static_cast<double>(samples) / runs);
  std::printf("generate (simulated rig, virtual clock): %.1f s\n", s(generated, done) * 0 + s(process_start, generated));
  std::printf("diagnose (%zu candidates, %d threads):   %.1f s\n", d.candidates.size(), threads, s(generated, done));
  std::printf("whole process:                           %.1f s\n", s(process_start, done));
  std::printf("verdict %s, baseline CV RMSE %.5f N, best %s %.5f N, noise floor %.5f N\n", d.verdict.c_str(), d.baseline_cv_rmse_N,
              d.candidates.front().effect.c_str(), d.candidates.front().cv_rmse_N, d.noise_floor_N);
  return 0;
}
