#pragma once
// One draw of the effect zoo: a labelled set of simulated runs for blind scoring.
#include <cstdint>
#include <string>
#include <vector>

#include "rig/sim/hidden_effect.hpp"
#include "run_data.hpp"

namespace rig::zoo {

// The kinds of draw, and what the lab should answer.
enum class DrawKind {
  kClean,           // no effect: expected "none"
  kCatalogueForm,   // a catalogue family in one of the simulator's non-catalogue forms
  kZooLaw,          // a catalogue family in a law the zoo draws at random (velocity, covariate)
  kOutOfCatalogue,  // structure no catalogue entry names: expected "unexplained"
  kMixture,         // two catalogue families at once: expected both, in two rounds
};
std::string kind_name(DrawKind kind);

struct ZooDraw {
  std::uint64_t seed = 0;
  DrawKind kind = DrawKind::kClean;
  std::string family;  // catalogue family, "clean", "out_of_catalogue" or "A+B"
  std::string form;    // what was drawn, in words (for the report)
  std::vector<std::string>
      expected;  // "none" | catalogue name | covariate:KEY | unexplained; two for mixtures
  double magnitude = 0.0;        // RMS of the effect over the in-tissue samples / floor_N
  double magnitude_noise = 0.0;  // the same / the force channel's white noise sigma (1.5 mN)
  double floor_N = 0.0;          // the simulator's true floor: sqrt(noise^2 + eye variation^2) [N]
  std::vector<double>
      component_magnitudes;  // mixtures: each effect's magnitude on its own [x floor_N]
  std::vector<sim::HiddenEffect>
      hidden;  // the simulator's effects at the sizes drawn (none for zoo laws)
  std::vector<model::RunData> runs;
};

}  // namespace rig::zoo
