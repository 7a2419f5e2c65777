#include "spatial_ripple.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

std::vector<std::vector<double>> SpatialRipple::starts() const {
  std::vector<std::vector<double>> out;
  for (double period = 0.25; period <= 4.0; period *= 1.01) out.push_back({period});  // a ripple stays coherent over ~30 mm only within ~1 %
  return out;
}

void SpatialRipple::design(const SampleView& s, const double* p, double* row) const {
  fourier(s.x_mm / p[0], kHarmonics, row);
  row[2 * kHarmonics] = 1.0;
}

std::string SpatialRipple::evidence(const EvidenceInput& in) const {
  return format("the residual is periodic in displacement with a %.3f mm period (amplitude up to %.4f N, phase differs by run)",
                in.shared[0], largest_amplitude(in.run_coefficients));
}

}  // namespace rig::model::effects
