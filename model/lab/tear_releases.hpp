#pragma once
// Tears let go: while the blade cuts, a tear builds its force over its own length and then
// releases it at once, so the measured force drops within a millisecond or two. Aperiodic
// tearing has no period a held-out run could be scored on, but its state - how far the blade
// has travelled since the last release - is in the force record itself, as a compliant
// mount's lag is. A release is a drop between the means of kWindow samples before and after a
// sample of more than kSigmas of that difference's white noise, the largest within kWindow
// samples of it, at least 0.3 mm past the data's own puncture (its own drop is no tear) while
// inserting and with the carriage moving at over a quarter of its insertion speed over the whole
// window (a stop on the way in lets a rate law's force go as fast, and that is no tear); a run with
// fewer than three has none. It is known kWindow samples after it happened (the window's last
// sample), or, a drop of over 8 sigmas from one sample to the next, from the sample after that
// next one; never earlier: a sample's own travel since the last release is read off samples
// before it only, so a term built on it predicts no sample from itself.
#include <cstddef>
#include <vector>

#include "phases.hpp"
#include "run_data.hpp"

namespace rig::model {

struct TearReleases {
  std::vector<std::size_t> at;     // the last sample before each drop, in time order
  std::vector<std::size_t> known;  // the first sample whose prediction may use each release
  std::vector<double> drop_N;      // each drop's size (mean before - mean after) [N]
  std::vector<double> since_mm;    // per sample: travel since the last release known there [mm], -1
                                   // if none (or withdrawing)
};

// `velocity_mm_s`: per sample, the carriage's measured speed; `insertion_mm_s`: the run's own.
TearReleases find_tear_releases(const RunData& run, const Segmentation& seg,
                                const std::vector<double>& velocity_mm_s, double insertion_mm_s);

}  // namespace rig::model
