#pragma once
// A long synthetic run for archive and export tests: `samples` samples `period_s` apart, a slow
// advance (10 µm per sample) and a force that varies (0.1-0.2 N sawtooth over 1000 samples).
#include <cstddef>

#include "run_data.hpp"

namespace rig::testing {

inline model::RunData long_run(std::size_t samples, double period_s) {
  model::RunData run;
  run.source = "long.csv";
  run.set("eye_id", "LONG");
  run.t_s.resize(samples);
  run.x_mm.resize(samples);
  run.force_N.resize(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    run.t_s[i] = static_cast<double>(i) * period_s;
    run.x_mm[i] = static_cast<double>(i) * 1e-5;
    run.force_N[i] = 0.1 + static_cast<double>(i % 1000) * 1e-4;
  }
  return run;
}

}  // namespace rig::testing
