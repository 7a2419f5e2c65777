// bench-explain: how long the explainer takes on a typical session (9 simulated runs, 12 mm
// deep) with an effect outside the catalogue, and what it proposes. Median of --repeats.
// --sweep: what it proposes over seeds 21-24, with and without holds (6 mm, 3 s), for
// effect-free runs, x^2 while retracting (1e-4 N/mm^2) and blade wear (1e-4 N per use mm).
//   bench-explain [--runs 9] [--repeats 3] [--effect retraction_square|blade_wear|none] [--sweep]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "injected_effects.hpp"
#include "lab_scenarios.hpp"
#include "residual_explainer.hpp"

namespace {

using rig::model::explainer::Explanation;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void inject(std::vector<rig::model::RunData>& runs, const std::string& effect, double size) {
  if (effect == "retraction_square") rig::testing::add_retraction_square(runs, size);
  if (effect == "blade_wear") rig::testing::add_blade_wear(runs, size);
}

void sweep() {
  for (const std::uint64_t seed : {21, 22, 23, 24}) {
    for (const bool holds : {false, true}) {
      const std::vector<rig::model::RunData> clean = rig::testing::scenario_runs({}, seed, holds);
      for (const char* effect : {"none", "retraction_square", "blade_wear"}) {
        std::vector<rig::model::RunData> runs = clean;
        inject(runs, effect, 1e-4);
        const Explanation e =
            rig::model::explainer::explain(rig::model::ForceModel::paper_interpreted(), runs);
        std::printf("seed %d %-8s %-17s proposed %d  CV RMSE %.5f -> %.5f N (floor %.5f)  [%s]\n",
                    static_cast<int>(seed), holds ? "holds" : "no hold", effect, e.proposed ? 1 : 0,
                    e.baseline_cv_rmse_N, e.validated ? e.after_cv_rmse_N : e.baseline_cv_rmse_N,
                    e.noise_floor_N, e.where.c_str());
      }
    }
  }
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench-explain: the model lab's explainer on simulated runs"};
  int runs = 9;
  int repeats = 3;
  bool do_sweep = false;
  std::string effect = "retraction_square";
  app.add_option("--runs", runs, "number of runs")->check(CLI::Range(1, 1000));
  app.add_option("--repeats", repeats, "timed repetitions (median)")->check(CLI::Range(1, 20));
  app.add_option("--effect", effect, "injected effect")
      ->check(CLI::IsMember({"retraction_square", "blade_wear", "none"}));
  app.add_flag("--sweep", do_sweep, "proposals over seeds and effects instead of the timing");
  CLI11_PARSE(app, argc, argv);
  if (do_sweep) {
    sweep();
    return 0;
  }
  std::vector<rig::model::RunData> data;
  const auto specs = rig::sim::design_runs(
      {15, 16.5, 18}, {1.5, 2.5, 3.5}, {0.5, 2.0, 3.5, 1.0, 3.0, 2.5, 1.5, 0.8, 3.2}, 12.0, 0.0, 5);
  std::size_t samples = 0;
  for (int i = 0; i < runs; ++i) {
    rig::sim::RunSpec spec = specs[static_cast<std::size_t>(i) % specs.size()];
    spec.seed += static_cast<std::uint64_t>(i) * 7919;
    data.push_back(rig::sim::generate_run({}, spec));
    samples += data.back().size();
  }
  inject(data, effect, 2e-4);
  std::vector<double> whole, unvalidated;
  Explanation e;
  for (int k = 0; k < repeats; ++k) {
    auto start = std::chrono::steady_clock::now();
    e = rig::model::explainer::explain(rig::model::ForceModel::paper_interpreted(), data);
    whole.push_back(seconds_since(start));
    rig::model::explainer::ExplainOptions quick;
    quick.validate = false;
    start = std::chrono::steady_clock::now();
    rig::model::explainer::explain(rig::model::ForceModel::paper_interpreted(), data, quick);
    unvalidated.push_back(seconds_since(start));
  }
  std::printf("runs %d, samples %zu, effect %s, %zu candidate features\n", runs, samples,
              effect.c_str(), e.library_size);
  std::printf("explain, median of %d: %.2f s (without the validating fit: %.2f s)\n", repeats,
              median(whole), median(unvalidated));
  std::printf("%s\nwhere %s; CV RMSE %.5f -> %.5f N, noise floor %.5f N\n", e.summary.c_str(),
              e.where.c_str(), e.baseline_cv_rmse_N, e.after_cv_rmse_N, e.noise_floor_N);
  return 0;
}
