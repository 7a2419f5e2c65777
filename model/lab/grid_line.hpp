#pragma once
// The frequency of the mains grid as one run saw it [Hz]: the strongest spectral line of the
// force channel within +-0.3 Hz of a nominal 50 or 60 Hz. Grids run off their nominal by
// hundredths of a hertz and wander; over a 20-40 s run a shared frequency slips by whole
// cycles, so mains pick-up is fitted at each run's own line (mains_interference). Estimated
// from the run's own samples, like the run's other nuisance parameters (own eye, drift).
#include <vector>

namespace rig::model {

// Strongest line of `force_N` sampled at `t_s` within nominal_hz +- 0.3 Hz, to ~0.002 Hz;
// `nominal_hz` when the run is too short (< 2 s) or too slowly sampled (< 150 Hz) to tell.
double grid_line_hz(const std::vector<double>& t_s, const std::vector<double>& force_N,
                    std::size_t begin, std::size_t end, double nominal_hz);

// The grid's phase through the run [cycles since t_s[begin]], one value per sample (before
// `begin`: the line's plain phase): the line at `line_hz` plus the slow wander of the grid
// around it, tracked by complex demodulation of the force's first differences at the line
// and a +-0.5 s moving average (its nulls at whole hertz remove the harmonics). A grid
// wandering by hundredths of a hertz moves the phase by tenths of a cycle over seconds,
// which constant coefficients cannot follow (and the 3rd and 5th harmonics three and five
// times more). Where the run carries no pick-up it tracks noise, harmlessly: the
// coefficients fitted on it are then ~0.
std::vector<double> grid_cycles(const std::vector<double>& t_s, const std::vector<double>& force_N,
                                std::size_t begin, double line_hz);

}  // namespace rig::model
