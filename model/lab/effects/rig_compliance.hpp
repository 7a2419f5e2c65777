#pragma once
// rig_compliance: the load cell and keratome mount give way, so the tip lags the measured
// carriage by a shift that grows with the measured force F; the model is evaluated at the
// tip, x - shift(F). The family covers the mounts of a bench rig:
//   linear       shift = c F                      (a spring)
//   polynomial   shift = c1 F + c2 F^2            (softening c2 > 0, stiffening c2 < 0)
//   stiffening   shift = c F / (1 + F / F0)       (a hardening mount: stiffness grows with load)
//   softening    shift = c F / (1 - F / F0)       (a yielding mount: stiffness (1 - F/F0)^2 / c
//                                                   falls towards a yield force F0; past 0.9 F0
//                                                   it stays at 1 % of its no-load value)
// The release after the deepest point is measured from the tip's own front, the carriage's
// front less the lag of the force the carriage left it with (PreparedRun::front_force_N):
// backing off, the carriage unloads the mount before the tip moves, by the same lag for
// every eye. The lag is that of the force averaged over +-5 samples (PreparedRun::
// mean_force_N): a sample's white noise is the load cell's, not the mount's load.
#include "family_term.hpp"

namespace rig::model::effects {

class RigCompliance final : public FamilyTerm {
 public:
  enum Form { kLinear = 0, kPolynomial, kStiffening, kSoftening };
  explicit RigCompliance(int form = kPolynomial) : FamilyTerm(form_names(), form) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "rig_compliance"; }
  std::string meaning() const override {
    return "the keratome tip lags the measured carriage by F/k (compliant mount)";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  bool fit_each_start() const override;
  double x_shift(const SampleView& s, const double* p) const override;
  double front_shift(const SampleView& s, const double* p) const override;
  std::string evidence(const EvidenceInput& in) const override;
  double lag(double force_N, const double* p) const;

 private:
  // Share of the yield force F0 up to which the softening form is c F / (1 - F/F0).
  static constexpr double kYieldShare = 0.9;
  static std::vector<std::vector<double>> softening_starts();
  static double yielding_lag(double force_N, double c_mm_N, double f0_N);
};

}  // namespace rig::model::effects
