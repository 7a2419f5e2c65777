#include "sim_commands.hpp"

#include <filesystem>
#include <iostream>

#include "run_csv.hpp"
#include "run_generator.hpp"

namespace rig::cli {
namespace {

struct GenerateOptions {
  std::string out = "sim-runs";
  std::vector<std::string> effects;
  std::vector<double> iops = {15, 16, 17, 18};
  std::vector<double> velocities = {1, 2, 3};
  std::vector<double> covariates = {0.5, 1.5, 2.5, 3.5, 1.0, 3.0};
  std::string covariate_key = "post_mortem_h";
  double depth_mm = 14.0;
  double hold_s = 0.0;
  std::uint64_t seed = 1;
};

int generate(const CliContext& c, const GenerateOptions& o) {
  sim::GeneratorOptions g;
  g.covariate_key = o.covariate_key;
  for (const auto& spec : o.effects) {
    std::string error;
    const auto effect = sim::parse_hidden_effect(spec, error);
    if (!effect) throw CLI::ValidationError("--effect", error);
    g.effects.push_back(*effect);
  }
  std::filesystem::create_directories(o.out);
  std::size_t n = 0;
  for (const sim::RunSpec& spec :
       sim::design_runs(o.iops, o.velocities, o.covariates, o.depth_mm, o.hold_s, o.seed)) {
    const model::RunData run = sim::generate_run(g, spec);
    const std::string path = o.out + "/" + spec.eye_id + ".csv";
    model::write_run_csv(run, path);
    ++n;
    if (!c.json())
      std::cerr << path << ": IOP " << spec.iop_mmHg << " mmHg, " << spec.velocity_mm_s << " mm/s, "
                << run.size() << " samples\n";
  }
  std::cout << (c.json() ? "{\"runs\":" + std::to_string(n) + ",\"out\":\"" + o.out + "\"}"
                         : std::to_string(n) + " runs written to " + o.out)
            << "\n";
  return 0;
}

}  // namespace

void add_sim_commands(CLI::App& app, CliContext& c, int& exit_code) {
  CLI::App* sim = app.add_subcommand("sim", "the simulated rig")->require_subcommand(1);
  auto o = std::make_shared<GenerateOptions>();
  CLI::App* gen = sim->add_subcommand(
      "generate", "simulated runs as run-CSV files, optionally with hidden effects");
  gen->add_option("--out", o->out, "output folder");
  gen->add_option("--effect", o->effects,
                  "hide an effect: name[:form][=size], covariate:KEY[:form][=size]");
  gen->add_option("--iops", o->iops, "IOPs [mmHg]")->delimiter(',');
  gen->add_option("--velocities", o->velocities, "velocities [mm/s]")->delimiter(',');
  gen->add_option("--covariates", o->covariates,
                  "values of the eyes' covariate, cycled over the runs")
      ->delimiter(',');
  gen->add_option("--covariate-key", o->covariate_key, "metadata key of that covariate");
  gen->add_option("--depth", o->depth_mm, "insertion depth [mm]");
  gen->add_option("--hold", o->hold_s, "hold at depth [s]");
  gen->add_option("--seed", o->seed, "random seed");
  gen->callback([&c, &exit_code, o] { exit_code = generate(c, *o); });
}

}  // namespace rig::cli
