// bench-explain: how long the explainer takes on a typical session (9 simulated runs, 12 mm
// deep) with an effect outside the catalogue, and what it proposes. Median of --repeats.
//   bench-explain [--runs 9] [--repeats 3] [--effect retraction_square|blade_wear|none]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "injected_effects.hpp"
#include "residual_explainer.hpp"
#include "run_generator.hpp"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench-explain: the model lab's explainer on simulated runs"};
  int runs = 9;
  int repeats = 3;
  std::string effect = "retraction_square";
  app.add_option("--runs", runs, "number of runs")->check(CLI::Range(1, 1000));
  app.add_option("--repeats", repeats, "timed repetitions (median)")->check(CLI::Range(1, 20));
  app.add_option("--effect", effect, "injected effect")->check(CLI::IsMember({"retraction_square", "blade_wear", "none"}));
  CLI11_PARSE(app, argc, argv);
  std::vector<rig::model::RunData> data;
  const auto specs = rig::sim::design_runs({15, 16.5, 18}, {1.5, 2.5, 3.5}, {0.5, 2.0, 3.5, 1.0, 3.0, 2.5, 1.5, 0.8, 3.2}, 12.0, 0.0, 5);
  std::size_t samples = 0;
  for (int i = 0; i < runs; ++i) {
    rig::sim::RunSpec spec = specs[static_cast<std::size_t>(i) % specs.size()];
    spec.seed += static_cast<std::uint64_t>(i) * 7919;
    data.push_back(rig::sim::generate_run({}, spec));
    samples += data.back().size();
  }
  if (effect == "retraction_square") rig::testing::add_retraction_square(data, 2e-4);
  if (effect == "blade_wear") rig::testing::add_blade_wear(data, 2e-4);
  std::vector<double> whole, unvalidated;
  rig::model::explainer::Explanation e;
  for (int k = 0; k < repeats; ++k) {
    auto start = std::chrono::steady_clock::now();
    e = rig::model::explainer::explain(rig::model::ForceModel::paper_interpreted(), data);
    whole.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    rig::model::explainer::ExplainOptions quick;
    quick.validate = false;
    start = std::chrono::steady_clock::now();
    rig::model::explainer::explain(rig::model::ForceModel::paper_interpreted(), data, quick);
    unvalidated.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::printf("runs %d, samples %zu, effect %s, %zu candidate features\n", runs, samples, effect.c_str(), e.library_size);
  std::printf("explain, median of %d: %.2f s (without the validating fit: %.2f s)\n", repeats, median(whole), median(unvalidated));
  std::printf("%s\nwhere %s; CV RMSE %.5f -> %.5f N, noise floor %.5f N\n", e.summary.c_str(), e.where.c_str(), e.baseline_cv_rmse_N,
              e.after_cv_rmse_N, e.noise_floor_N);
  return 0;
}
