// bench-lab: the model lab's headline figures (docs/model-lab.md).
//  1. The blind effect zoo: diagnose on hundreds of seeded draws (sim/zoo), rates against
//     the targets. 2. Diagnose time on 100 simulated runs of ~15,000 samples: one pass, or
//     with --timing the benchmark, median of 3 passes (target < 30 s).
//   bench-lab [--draws 200] [--seed 1000] [--verbose] [--no-zoo] [--clean-only]
//             [--only catalogue,law] [--min-magnitude 3]
//             [--runs 100] [--threads 2] [--effect shaft_friction] [--timing | --no-timing]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "diagnosis.hpp"
#include "run_csv.hpp"
#include "run_generator.hpp"
#include "zoo_scorer.hpp"

namespace {

double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

std::vector<rig::model::RunData> timing_runs(int runs, const std::string& effect) {
  rig::sim::GeneratorOptions g;
  if (!effect.empty()) {
    std::string error;
    const auto parsed = rig::sim::parse_hidden_effect(effect, error);
    if (!parsed) throw CLI::ValidationError("--effect", error);
    g.effects.push_back(*parsed);
  }
  std::vector<rig::model::RunData> data;
  // The zoo's protocol (two stops on the way in, a hold at depth: every candidate, relaxation
  // included, has something to fit) at 1-3 mm/s with approach and retraction.
  const auto specs = rig::sim::design_runs({15, 16, 17, 18, 15.5}, {1, 1.5, 2, 2.5, 3},
                                           {0.5, 1.5, 2.5, 3.5}, 14.0, 0.0, 9);
  for (int i = 0; i < runs; ++i) {
    rig::sim::RunSpec spec = specs[static_cast<std::size_t>(i) % specs.size()];
    rig::sim::apply_standard_protocol(spec);
    spec.seed += static_cast<std::uint64_t>(i) * 7919;
    spec.eye_id += "-" + std::to_string(i);
    data.push_back(rig::sim::generate_run(g, spec));
  }
  return data;
}

void diagnose_timing(int runs, int threads, const std::string& effect, int repeats) {
  const auto start = std::chrono::steady_clock::now();
  const auto data = timing_runs(runs, effect);
  std::size_t samples = 0;
  for (const auto& r : data) samples += r.size();
  const auto generated = std::chrono::steady_clock::now();
  std::printf("\ndiagnose time: %d runs, %zu samples (%.0f per run), simulated in %.1f s\n", runs,
              samples, static_cast<double>(samples) / runs, seconds(start, generated));
  rig::model::DiagnoseOptions options;
  options.threads = threads;
  std::vector<double> times;
  rig::model::Diagnosis d;
  for (int k = 0; k < repeats; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t cpu0 = std::clock();
    d = rig::model::diagnose(rig::model::ForceModel::paper_interpreted(), data, options);
    times.push_back(seconds(t0, std::chrono::steady_clock::now()));
    // CPU seconds of all threads: on a shared machine the wall time says more about the load.
    const double cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    std::printf("  diagnose pass %d (%zu candidates, %d threads): %.1f s wall, %.1f s CPU\n", k + 1,
                d.candidates.size(), threads, times.back(), cpu_s);
  }
  std::sort(times.begin(), times.end());
  std::printf("  median of %d: %.1f s (target < 30 s)\n", repeats, times[times.size() / 2]);
  std::printf("  verdict %s, baseline CV RMSE %.5f N, best %s %.5f N, noise floor %.5f N\n",
              d.verdict.c_str(), d.baseline_cv_rmse_N, d.candidates.front().effect.c_str(),
              d.candidates.front().cv_rmse_N, d.noise_floor_N);
}

// Draws of the listed kinds only (clean, catalogue, law, outside, mixture), or all kinds
// (empty); magnitudes log-uniform from `min_magnitude` [x the true floor] to the zoo's top.
// `--only catalogue,law --min-magnitude 3` draws exactly the population of the headline bar
// (catalogue families in other forms, >= 3x the floor), each with the same conditional law of
// magnitude as in the full zoo, so that bar is measured on many draws in one run.
rig::zoo::ZooOptions zoo_options(const std::vector<std::string>& only, double min_magnitude) {
  rig::zoo::ZooOptions o;
  o.min_magnitude = min_magnitude;
  if (only.empty()) return o;
  double* shares[] = {&o.clean_share, &o.catalogue_share, &o.zoo_law_share,
                      &o.out_of_catalogue_share, &o.mixture_share};
  const char* names[] = {"clean", "catalogue", "law", "outside", "mixture"};
  for (int k = 0; k < 5; ++k) {
    if (std::find(only.begin(), only.end(), names[k]) == only.end()) *shares[k] = 0.0;
  }
  return o;
}

}  // namespace

// The draws' runs as run-CSV, with what each hides, so that a draw can be diagnosed by hand.
int save_draws(const rig::zoo::ZooGenerator& generator, const rig::zoo::ScoreOptions& o,
               const std::string& dir) {
  for (int k = 0; k < o.draws; ++k) {
    const std::uint64_t seed = o.first_seed + static_cast<std::uint64_t>(k);
    rig::zoo::ZooDraw draw;
    try {
      draw = generator.draw(seed);
    } catch (const rig::sim::RunFaulted& e) {
      std::printf("draw %llu not run: %s\n", static_cast<unsigned long long>(seed), e.what());
      continue;
    }
    const std::string folder = dir + "/" + std::to_string(draw.seed);
    std::filesystem::create_directories(folder);
    for (std::size_t r = 0; r < draw.runs.size(); ++r)
      rig::model::write_run_csv(draw.runs[r], folder + "/run-" + std::to_string(r) + ".csv");
    std::printf("%s: %s, %s, %.2fx the floor (%.1f mN), expected %s\n", folder.c_str(),
                draw.family.c_str(), draw.form.c_str(), draw.magnitude, 1e3 * draw.floor_N,
                draw.expected.front().c_str());
  }
  return 0;
}

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // figures appear as they come, also into a file
  CLI::App app{"bench-lab: the model lab's blind-zoo rates and diagnose time"};
  rig::zoo::ScoreOptions zoo;
  bool no_zoo = false;
  bool clean_only = false;
  bool timing = false;
  bool no_timing = false;
  int runs = 100;
  std::string effect = "shaft_friction";
  std::string save_dir;
  app.add_option("--draws", zoo.draws, "zoo draws to score (a quick look: 20)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--seed", zoo.first_seed, "first draw's seed (draw k has seed + k)");
  app.add_flag("--verbose", zoo.verbose,
               "two lines per draw on stderr, and the table so far every 10 draws");
  app.add_flag("--no-zoo", no_zoo, "skip the zoo");
  app.add_flag("--clean-only", clean_only,
               "effect-free draws only (to calibrate the false-alarm bars on tuning seeds)");
  std::vector<std::string> only;
  app.add_option("--only", only, "draws of these kinds only (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember({"clean", "catalogue", "law", "outside", "mixture"}));
  double min_magnitude = rig::zoo::ZooOptions{}.min_magnitude;
  app.add_option("--min-magnitude", min_magnitude,
                 "smallest drawn magnitude [x the true floor] (3: the headline bar's draws)")
      ->check(CLI::Range(0.1, rig::zoo::ZooOptions{}.max_magnitude));
  app.add_option("--threads", zoo.threads, "diagnose's worker threads")->check(CLI::Range(1, 64));
  app.add_flag("--timing", timing, "diagnose time as the median of 3 passes (the 30 s benchmark)");
  app.add_flag("--no-timing", no_timing, "skip the diagnose time");
  app.add_option("--runs", runs, "runs for the diagnose time")->check(CLI::Range(1, 10000));
  app.add_option("--effect", effect, "hidden effect of the diagnose-time runs (empty: clean)");
  app.add_option("--save-runs", save_dir,
                 "write each draw's runs as run-CSV files into DIR/SEED/ (for `rig model "
                 "diagnose`), no scoring");
  CLI11_PARSE(app, argc, argv);
  if (clean_only) only = {"clean"};
  if (!save_dir.empty())
    return save_draws(rig::zoo::ZooGenerator{zoo_options(only, min_magnitude)}, zoo, save_dir);
  if (!no_zoo) {
    const auto start = std::chrono::steady_clock::now();
    const rig::zoo::ZooScore score =
        rig::zoo::score_zoo(rig::zoo::ZooGenerator{zoo_options(only, min_magnitude)}, zoo);
    rig::zoo::print_score(score, stdout);
    std::printf(
        "  (seeds %llu..%llu, %.0f s in all)\n", static_cast<unsigned long long>(zoo.first_seed),
        static_cast<unsigned long long>(zoo.first_seed + static_cast<std::uint64_t>(zoo.draws) - 1),
        seconds(start, std::chrono::steady_clock::now()));
  }
  if (!no_timing) diagnose_timing(runs, zoo.threads, effect, timing ? 3 : 1);
  return 0;
}
