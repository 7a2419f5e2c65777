#pragma once
// Compare: where does the model fail? The model (with whatever effects its file carries)
// against measured runs - by run, by phase, by 1 mm depth band, against every numeric
// covariate and extra channel, and the residual spectrum in time and in displacement.
#include <string>
#include <vector>

#include "force_model.hpp"
#include "phases.hpp"
#include "run_data.hpp"
#include "segment_metrics.hpp"

namespace rig::model {

struct CovariateTrend {
  std::string key;
  double correlation = 0.0;  // Pearson, run RMSE against the run's mean value
  double slope_N_per_unit = 0.0;
  std::vector<double> values;
  std::vector<double> run_rmse_N;
};

struct SpectrumPeak {
  double frequency = 0.0;  // [Hz] in time, [1/mm] in displacement
  double amplitude_N = 0.0;
};

struct RunComparison {
  std::string label;
  Segmentation segmentation;
  std::vector<double> prediction;  // per sample
  SegmentMetrics overall;
};

struct Comparison {
  std::string model_name;
  std::vector<RunComparison> runs;
  std::vector<SegmentMetrics> by_phase;
  std::vector<SegmentMetrics> by_depth;  // 1 mm bands of the insertion
  std::vector<CovariateTrend> covariates;
  std::vector<SpectrumPeak> time_spectrum;                  // strongest peaks
  std::vector<SpectrumPeak> displacement_spectrum;          // strongest peaks
  std::vector<double> time_frequency_Hz, time_amplitude_N;  // the averaged spectra, for plots
  std::vector<double> x_frequency_per_mm, x_amplitude_N;
  SegmentMetrics overall;
  double noise_floor_N = 0.0;
  std::vector<std::string> warnings;
};

// With `refit`, the model's parameters are first fitted across the runs (the family).
Comparison compare(const ForceModel& model, const std::vector<RunData>& runs, bool refit = false);

}  // namespace rig::model
