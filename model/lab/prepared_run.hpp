#pragma once
// A run made ready for fitting: its phases, smoothed velocity, time in hold, inserted blade
// length, the samples analysed (from first contact on) and a decimated subset for fits.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "phases.hpp"
#include "run_data.hpp"
#include "tear_releases.hpp"

namespace rig::model {

// One sample's inputs to the model side by side. A fit visits about one sample in twenty of
// each run, and one record per sample costs it one cache miss where six separate arrays cost
// six: on 100 runs those misses were the largest single cost of a diagnosis.
struct SampleInputs {
  double x_mm = 0.0;
  double t_s = 0.0;
  double force_N = 0.0;        // measured
  double velocity_mm_s = 0.0;  // as `velocity_mm_s` below
  double hold_s = 0.0;         // as `hold_s` below
  double front_mm = 0.0;       // as `front_mm` below
  double grid_cycles[2] = {
      0.0,
      0.0};  // the 50 and 60 Hz grid's tracked phase [cycles] (grid_line.hpp), NaN before contact
  Phase phase = Phase::kApproach;
  double front_force_N = 0.0;  // as `front_force_N` below
  double mean_force_N = 0.0;   // as `mean_force_N` below
};

struct PreparedRun {
  const RunData* data = nullptr;
  Segmentation seg;
  std::vector<double> velocity_mm_s;  // dx/dt over +-10 ms (irregular sampling safe)
  std::vector<double> hold_s;  // time since the hold (or a stop on the way in) began, 0 outside it
  std::vector<double>
      reload_mm;  // after a stop on the way in: advance since it ended [mm], else -1
  std::vector<double> stop_length_s;  // ... and that stop's length [s]
  std::vector<double> inserted_mm;    // blade length past the detected puncture (reports)
  std::vector<double> front_mm;       // deepest displacement so far
  std::vector<double> front_force_N;  // measured force when the carriage was last at its front [N]
  std::vector<double>
      mean_force_N;  // measured force averaged over +-5 samples [N] (a mount's lag follows it)
  TearReleases
      tears;  // the force's own drops past the puncture, and travel since the last (stick_slip)
  std::vector<std::size_t> analysed;  // from first contact to the end
  std::vector<std::size_t>
      fit_rows;  // `analysed` thinned to one jittered row per stride, for the nonlinear fits
  std::vector<SampleInputs>
      inputs;  // per sample: a copy of the above, packed for the fits (set last)
  std::vector<SampleInputs>
      fit_inputs;  // inputs[fit_rows[n]] in order, read front to back by the fits (pack_fit_rows)
  double parked_mm = 0.0;  // mean position of the first 20 samples, where the force was tared [mm]
  double iop_mmHg = 15.0;
  double velocity_cmd_mm_s = 2.0;  // insertion velocity (metadata, else measured)
  bool iop_known = false;
  bool velocity_known = false;
  double grid_hz[2] = {
      50.0,
      60.0};  // the run's own mains lines near 50 and 60 Hz (grid_line.hpp); phases in `inputs`
  std::map<std::string, double> derived;  // covariates derived from the whole run set (run_order)
  std::vector<std::string> warnings;
  std::map<std::string, double> metadata_numbers;  // the metadata's numeric values, parsed once

  std::size_t size() const { return data->size(); }
  // A numeric covariate: run metadata, or an extra channel's value at sample i.
  std::optional<double> covariate(const std::string& key, std::size_t i) const;
  std::string label() const { return data->label(); }
};

PreparedRun prepare_run(const RunData& run, std::size_t max_fit_rows = 800);
// After `fit_rows` changed: copy their inputs side by side into `fit_inputs`. A fit reads
// them hundreds of times; scattered over a 100-run set they cost a cache and a TLB miss each.
void pack_fit_rows(PreparedRun& run);

// The row kept of stratum k = [lo, hi) of a run's n analysed samples when they are thinned
// (fit rows, scored samples): a fixed pseudo-random place in the stratum, a hash of k and n
// alone, so that rows are as evenly spread as a stride, never at one phase of mains pick-up
// (an even stride at 1 kHz is often whole 50/60 Hz cycles), reproducible, and never
// dependent on another run (a fold's rows do not change with its held-out runs).
std::size_t jittered_row(std::size_t k, std::size_t lo, std::size_t hi, std::size_t n);

// Fit rows and scored samples for a set of `runs` runs holding `samples` analysed samples
// in all: up to 800 fit rows per run while the set is small, fewer (not under 100) beyond
// 12 runs, so that a fit sees at most ~10,000 rows (100 runs: 100 each, still 10x the most
// per-run coefficients of any term, and a diagnosis stays under 30 s on 2 cores); every analysed
// sample is scored up to 250,000 in all, beyond that evenly thinned (100 runs x 15,000 samples:
// 2,500 per run). 2026-11-28: 16,000 rows and 400,000 scored samples had grown to 40 s with the
// forms added since 2026-11-24; the zoo's 9-run draws keep 800 rows and every sample.
struct RowBudget {
  std::size_t fit_rows_per_run = 800;
  std::size_t scored_per_run = 0;  // 0: every analysed sample
};
RowBudget row_budget(std::size_t runs, std::size_t samples);
// Keep at most `max_rows` analysed samples, one jittered row per stratum (0: all).
void thin_analysed(PreparedRun& run, std::size_t max_rows);

// Run order within a session as the covariate `run_order` (1, 2, ... by `started_at`; a
// session is the runs sharing a `session` metadata value, else the same date), so that
// wear across a session shows. Left out unless every run has `started_at`.
void add_run_order(std::vector<PreparedRun>& runs);

}  // namespace rig::model
