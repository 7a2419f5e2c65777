#pragma once
// Checks that keep the lab honest on data it was not made for.
//  - Digitized sampling: curves digitized from a paper's figure (or resampled by hand)
//    have irregular, quantised sample times and repeated points; their fine structure is
//    the digitizer's steps, not the instrument's. Candidates whose evidence rests on fine
//    periodic structure (spatial_ripple, mains_interference, stick_slip) are then not
//    applicable. A run is digitized if its metadata says so (`digitized: yes`), if a time
//    repeats or goes back, or if its base interval (10th percentile) is not its commonest:
//    fewer than 20 % of the intervals within 10 % of it, or more at some multiple 2..8 of
//    it (a DAQ samples at one period; lost samples make gaps of whole periods, rarer the
//    longer they are, so the period stays the commonest even with 60 % lost at random).
//  - Base misfit: the paper's model describes ovine cornea under a keratome. On other
//    tissue or tools (the needle-in-liver data) even the refitted baseline misses most of
//    the signal, and any "effect" found on top of it is not to be trusted; say so.
#include <string>
#include <vector>

#include "comparison.hpp"
#include "prepared_run.hpp"

namespace rig::model {

struct SamplingCheck {
  bool digitized = false;
  std::string why;  // for the first digitized run, in words
};

SamplingCheck check_sampling(const RunData& run);
SamplingCheck check_sampling(const std::vector<const PreparedRun*>& runs);
// Whether `effect` may be fitted to these runs; if not, `why_not` says why.
bool sampling_allows(const std::string& effect, const std::vector<const PreparedRun*>& runs,
                     std::string& why_not);
// One warning per digitized data set (empty if none).
void append_sampling_warnings(const std::vector<const PreparedRun*>& runs,
                              std::vector<std::string>& warnings);

// Warnings when the refitted baseline (compare with refit) does not describe the data:
// R^2 of the insertion below kMinBaselineR2, no puncture found, or puncture depths far from
// the model's Table 1.
inline constexpr double kMinBaselineR2 = 0.9;
std::vector<std::string> base_misfit_warnings(const ForceModel& model, const Comparison& refitted);

}  // namespace rig::model
