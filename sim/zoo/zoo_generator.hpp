#pragma once
// The effect zoo: draws effects from a broad space, independently of the model lab's terms,
// and simulates a set of runs for each, all with the same protocol (apply_standard_protocol:
// stops before and after the puncture, a hold at depth), IOP 15-18 mmHg, 0.5-4 mm/s, eyes
// varying. Every draw is reproducible from its seed. Magnitudes are set relative to the
// simulator's true floor (the "measurement noise + eye variation"): the effect's RMS
// over the in-tissue samples of three pilot runs, measured against the same runs without it,
// scales the draw to the wanted multiple of that floor, itself measured on the same pilot
// runs as the RMS of white noise and of the difference between varying and identical eyes.
#include <cstdint>

#include "run_generator.hpp"
#include "zoo_draw.hpp"

namespace rig::zoo {

struct Recipe;  // what a draw hides (zoo_generator.cpp)

struct ZooOptions {
  int runs = 9;                // runs per draw (3 IOP x 3 velocity levels, jittered)
  double min_magnitude = 0.5;  // x the true floor (noise + eye variation), drawn log-uniformly
  double max_magnitude = 10.0;
  // Share of each kind (need not sum to 1).
  double clean_share = 0.2, catalogue_share = 0.4, zoo_law_share = 0.15,
         out_of_catalogue_share = 0.15, mixture_share = 0.1;
};

class ZooGenerator {
 public:
  explicit ZooGenerator(ZooOptions options = {}) : o_(options) {}
  ZooDraw draw(std::uint64_t seed) const;
  // The run specifications of a draw (protocol, IOP, velocity, covariates), effect-free.
  std::vector<sim::RunSpec> run_specs(std::uint64_t seed) const;

 private:
  Recipe recipe(std::uint64_t seed) const;
  static constexpr std::size_t kPilotRuns =
      3;  // runs simulated to measure a magnitude or the floor
  double pilot_magnitude(const Recipe& r, const std::vector<sim::RunSpec>& specs, double size,
                         std::size_t runs = kPilotRuns) const;
  std::vector<double> calibrate_components(Recipe& r, const std::vector<sim::RunSpec>& specs,
                                           double floor_in_noise) const;
  // The simulator's own floor for these runs [N]: RMS of white noise and eye-to-eye variation.
  double true_floor_N(const std::vector<sim::RunSpec>& specs) const;
  std::vector<model::RunData> simulate(const Recipe& r, const std::vector<sim::RunSpec>& specs,
                                       double size, std::size_t count,
                                       double eye_variability = 1.0) const;
  ZooOptions o_;
};

// Effect RMS over in-tissue samples of `with` against `without`, in units of `noise_N`.
double effect_rms_ratio(const std::vector<model::RunData>& with,
                        const std::vector<model::RunData>& without, double noise_N);

}  // namespace rig::zoo
