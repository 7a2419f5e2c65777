#include "mains_interference.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& MainsInterference::form_names() {
  static const std::vector<std::string> kNames = {"3 harmonics", "sine", "chirp"};
  return kNames;
}

std::vector<ParamSpec> MainsInterference::shared_params() const {
  const ParamSpec frequency{"frequency", "Hz", 50.0, 45.0, 65.0};
  if (form_ == kSine) return {frequency, {"harmonics", kFormLabelUnit, 1.0, 0.5, 1.5}};
  if (form_ == kChirp) return {frequency, {"chirp", "Hz/s", 0.0, -0.5, 0.5}};
  return {frequency};
}

std::vector<std::vector<double>> MainsInterference::starts() const {
  if (form_ == kThreeHarmonics) return {{50.0}, {60.0}};
  if (form_ == kSine) return {{50.0, 1.0}, {60.0, 1.0}};
  std::vector<std::vector<double>> out;
  for (const double f : {50.0, 60.0}) {
    for (const double chirp : {-0.02, 0.0, 0.02}) out.push_back({f, chirp});
  }
  return out;
}

bool MainsInterference::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
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

void MainsInterference::design(const SampleView& s, const double* p, double* row) const {
  if (form_ == kChirp) {
    const double t = s.t_s - s.run->data->t_s.front();
    fourier(t * (p[0] + 0.5 * p[1] * t), 1, row);
    return;
  }
  fourier(s.t_s * p[0], form_ == kThreeHarmonics ? 3 : 1, row);
}

std::string MainsInterference::evidence(const EvidenceInput& in) const {
  std::string shape = form_ == kSine ? "sinusoidal pick-up: " : (form_ == kChirp ? "pick-up with a drifting frequency: " : "pick-up with 3 harmonics: ");
  if (form_ == kChirp) shape += format("%+.3f Hz/s; ", in.shared[1]);
  return shape + format("the residual oscillates at %.2f Hz in time (amplitude up to %.4f N), the mains frequency", in.shared[0],
                        largest_amplitude(in.run_coefficients)) + honesty(in);
}

}  // namespace rig::model::effects
