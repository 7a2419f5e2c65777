#pragma once
// Offset steps of the force channel: a load cell's zero can jump (a connector, a thermal EMF,
// a gauge that slips), and a downward jump before the puncture looks like the puncture's own
// drop. A jump is told from the tissue by what the force does around it: a straight line in
// time is fitted on each side of every sample (windows of kWindow_s, leaving kGap_s on each
// side for the jump's own width), and a jump is where the two lines disagree at the sample by
// far more than their noise, and most samples on each side stand off the other side's line
// by at least half the jump (a dip of a few ms pulls a line, not the median). It is a sensor
// offset, not the tissue, when the force's slope in displacement goes on unchanged across it
// (the puncture loses the intact cornea's stiffness, a release at reversal ends the load;
// slopes compared over 0.4 mm of travel each side), when the carriage stands at it (a tissue
// at rest relaxes smoothly, it does not jump), or when it jumps up as the carriage stops more
// than 0.1 s after it (the force stops rising and relaxes). It is the tissue's when the
// carriage starts, reverses or parks at it, stops within 0.1 s of it (a rate law follows the
// speed), has advanced less than 0.6 mm since a stop (reloading, or a puncture as the blade
// sets off), or when the force drops onto its contact-free level and stays flat (the blade
// let go, or a soft mount snapping the tip through). Used by the phase detector (the puncture
// is found on the force less these steps) and by sensor_drift's step form (a column per step).
#include <cstddef>
#include <vector>

#include "run_data.hpp"

namespace rig::model {

struct OffsetStep {
  std::size_t index = 0;  // the sample at the jump
  double t_s = 0.0;       // its time [s]
  double size_N = 0.0;    // right level - left level [N]
};

struct LevelShiftOptions {
  double window_s = 0.15;   // each side's line fit [s]
  double gap_s = 0.015;     // left out on each side of the jump (its width) [s]
  double min_sigmas = 3.0;  // a jump is at least this many white-noise sigmas ...
  double min_se = 10.0;     // ... and this many standard errors of the two lines' difference
  std::size_t max_steps =
      3;  // more offset-like jumps than this in a run are a process (tearing), not steps
};

// The sensor offset steps of `run` in time order; `sigma_N` is the force channel's white noise.
std::vector<OffsetStep> find_offset_steps(const RunData& run, double sigma_N,
                                          const LevelShiftOptions& o = {});

// The force less every step from its time on [N], one value per sample.
std::vector<double> without_steps(const RunData& run, const std::vector<OffsetStep>& steps);

}  // namespace rig::model
