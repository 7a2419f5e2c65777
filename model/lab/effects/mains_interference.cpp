#include "mains_interference.hpp"

#include <algorithm>
#include <cmath>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& MainsInterference::form_names() {
  static const std::vector<std::string> kNames = {"5 harmonics", "sine", "chirp", "while moving"};
  return kNames;
}

std::vector<ParamSpec> MainsInterference::shared_params() const {
  const ParamSpec frequency{"frequency", "Hz", 50.0, 45.0,
                            65.0};  // the nominal; each run at its own line
  if (form_ == kSine) return {frequency, {"harmonics", kFormLabelUnit, 1.0, 0.5, 1.5}};
  if (form_ == kChirp) return {frequency, {"chirp", "Hz/s", 0.0, -0.5, 0.5}};
  if (form_ == kWhileMoving) return {frequency, {"while moving", kFormLabelUnit, 3.0, 2.5, 3.5}};
  return {frequency};
}

std::vector<std::vector<double>> MainsInterference::starts() const {
  if (form_ == kHarmonics) return {{50.0}, {60.0}};
  if (form_ == kSine) return {{50.0, 1.0}, {60.0, 1.0}};
  if (form_ == kWhileMoving) return {{50.0, 3.0}, {60.0, 3.0}};
  std::vector<std::vector<double>> out;
  for (const double f : {50.0, 60.0}) {
    for (const double chirp : {-0.02, 0.0, 0.02}) out.push_back({f, chirp});
  }
  return out;
}

bool MainsInterference::applicable(const std::vector<const PreparedRun*>& runs,
                                   std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    const double span = r->data->t_s.back() - r->data->t_s.front();
    const double rate = static_cast<double>(r->size()) / std::max(span, 1e-9);
    if (rate < 150.0) {
      why_not = "sampling below 150 Hz cannot show 50/60 Hz";
      return false;
    }
  }
  return true;
}

// The run's own grid frequency: its line near the nominal p[0] is closest to, moved by
// p[0]'s distance from that nominal (a shared correction, ~0 when the lines are right).
double MainsInterference::run_hz(const PreparedRun& run, double p0) {
  const int k = std::abs(p0 - 50.0) <= std::abs(p0 - 60.0) ? 0 : 1;
  return run.grid_hz[k] + (p0 - (k == 0 ? 50.0 : 60.0));
}

void MainsInterference::design(const SampleView& s, const double* p, double* row) const {
  const int k = std::abs(p[0] - 50.0) <= std::abs(p[0] - 60.0) ? 0 : 1;
  const double tracked = (s.inputs != nullptr ? *s.inputs : s.run->inputs[s.i]).grid_cycles[k];
  const double t = s.t_s - s.run->inputs.front().t_s;
  // The grid's tracked phase, moved by the shared correction of the nominal (~0).
  double cycles = (std::isnan(tracked) ? run_hz(*s.run, p[0]) * t : tracked) +
                  (p[0] - (k == 0 ? 50.0 : 60.0)) * t;
  if (form_ == kChirp) cycles += 0.5 * p[1] * t * t;
  fourier(cycles, form_ == kHarmonics ? kHarmonicCount : 1, row);
  // Picked up from the motor drive: none while the carriage stands (stops, the hold).
  const bool standing =
      s.phase == Phase::kHold || (s.hold_s > 0.0 && s.phase != Phase::kRetraction);
  if (form_ == kWhileMoving && standing) row[0] = row[1] = 0.0;
}

std::string MainsInterference::evidence(const EvidenceInput& in) const {
  std::string shape = form_ == kSine ? "sinusoidal pick-up: "
                                     : (form_ == kChirp ? "pick-up with a drifting frequency: "
                                                        : "pick-up with 5 harmonics: ");
  if (form_ == kWhileMoving)
    shape = "pick-up from the motor drive, only while the carriage moves: ";
  if (form_ == kChirp) shape += format("%+.3f Hz/s; ", in.shared[1]);
  double lo = 1e9, hi = -1e9;
  for (const PreparedRun* r : in.runs)
    lo = std::min(lo, run_hz(*r, in.shared[0])), hi = std::max(hi, run_hz(*r, in.shared[0]));
  return shape +
         format(
             "the residual oscillates at %.3f-%.3f Hz in time (each run's own grid line; amplitude "
             "up to %.4f N), the mains frequency",
             lo, hi, largest_amplitude(in.run_coefficients)) +
         honesty(in);
}

}  // namespace rig::model::effects
