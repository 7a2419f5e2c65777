#pragma once
// Blind scoring of the model lab on the effect zoo: runs `diagnose` (model/lab) on every
// draw and reports the lab's headline rates (docs/model-lab.md): correct verdicts on
// catalogue families in forms that are not the lab's, false alarms on effect-free sets,
// `unexplained` on out-of-catalogue structure, mixtures found in two rounds, and whether
// the named effect brings the CV error close to the floor.
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "zoo_generator.hpp"

namespace rig::zoo {

struct DrawScore {
  std::uint64_t seed = 0;
  DrawKind kind = DrawKind::kClean;
  std::string family, form;
  std::vector<std::string> expected;
  double magnitude = 0.0;        // x the simulator's true floor (noise + eye variation)
  double magnitude_noise = 0.0;  // x the white noise alone (the stricter scale)
  double true_floor_N = 0.0;     // the simulator's floor [N]
  std::string verdict;           // first round
  std::string first_named;       // mixtures: the first round's verdict, or its partial candidate
  std::string second_verdict;    // mixtures: with first_named in the base
  bool correct = false;          // the verdict (both, for mixtures) is what was expected
  double baseline_N = 0.0, floor_N = 0.0, after_N = 0.0;  // CV RMSE before/after the verdict, floor
  bool fit_close = false;  // after <= floor + 25 % of (baseline - floor)
  // For --verbose and calibration: the within-eye baseline against the measurement noise,
  // the candidate ranked first, and the largest gain any candidate reached on each channel.
  double own_eye_N = 0.0, measurement_N = 0.0;
  std::string best;
  double best_gain_pct = 0.0, best_own_eye_gain_pct = 0.0;
  double generate_s = 0.0, diagnose_s = 0.0;
};

struct Rate {
  int hits = 0, total = 0;
  double percent() const { return total > 0 ? 100.0 * hits / total : 0.0; }
};

// A draw whose runs the simulated rig could not complete: an interlock stopped one (a large
// effect can push the force past the load cell's limit, as on a real rig). It has no verdict
// and stands outside every rate; the table counts it.
struct DrawNotRun {
  std::uint64_t seed = 0;
  std::string why;
};

struct ZooScore {
  std::vector<DrawScore> draws;
  std::vector<DrawNotRun> not_run;
  Rate catalogue_correct;  // catalogue families (both kinds) at >= 3x the floor
  std::map<std::string, Rate> correct_by_family;
  Rate catalogue_correct_below_3x;  // the same under 3x (reported, no target)
  Rate catalogue_correct_3x_noise;  // at >= 3x the white noise alone (the stricter scale)
  Rate false_alarms;                // clean sets with a verdict other than none
  Rate unexplained;                 // out-of-catalogue sets answered `unexplained` (>= 3x)
  Rate mixtures_found;              // both effects named in two rounds
  Rate fit_close;                   // among correct verdicts
  Rate fit_close_3x;  // the same, among those at >= 3x the floor (reported, no target)
  double median_generate_s = 0.0, median_diagnose_s = 0.0;
};

struct ScoreOptions {
  std::uint64_t first_seed = 1000;
  int draws = 200;
  int threads = 2;       // diagnose's worker threads
  bool verbose = false;  // two lines per draw on stderr, and the table so far every 10 draws
};

DrawScore score_draw(const ZooDraw& draw, int threads);
ZooScore score_zoo(const ZooGenerator& generator, const ScoreOptions& options);
void summarise(ZooScore& score);
void print_score(const ZooScore& score, std::FILE* out);

}  // namespace rig::zoo
