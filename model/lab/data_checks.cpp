#include "data_checks.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>

#include "number_text.hpp"

namespace rig::model {
namespace {

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  return number_text(pattern, a, b, c);
}

bool says_digitized(const RunData& run) {
  const auto flag = run.text("digitized");
  if (!flag) return false;
  std::string v = *flag;
  std::transform(v.begin(), v.end(), v.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return v == "yes" || v == "true" || v == "1";
}

bool rests_on_fine_structure(const std::string& effect) {
  static const std::set<std::string> kFine = {"spatial_ripple", "mains_interference", "stick_slip"};
  return kFine.count(effect) != 0U;
}

}  // namespace

SamplingCheck check_sampling(const RunData& run) {
  if (says_digitized(run)) return {true, run.label() + ": its metadata says `digitized: yes`"};
  if (run.size() < 3) return {};
  std::vector<double> dt;
  std::size_t repeated = 0;
  for (std::size_t i = 1; i < run.size(); ++i) {
    const double step = run.t_s[i] - run.t_s[i - 1];
    if (step <= 0.0)
      ++repeated;
    else
      dt.push_back(step);
  }
  if (repeated > 0)
    return {true, run.label() + ": " + std::to_string(repeated) +
                      " sample time(s) repeat or go back (a DAQ never does)"};
  if (dt.size() < 2) return {};
  std::vector<double> sorted = dt;
  std::sort(sorted.begin(), sorted.end());
  // A DAQ's intervals are its period, or whole multiples of it where samples were lost, and
  // the period itself is the commonest (even with 60 % lost at random). A digitizer's steps
  // are multiples of its pixel quantum with no such order. Windows of +-10 % allow jitter.
  const double base = sorted[sorted.size() / 10];  // 10th percentile: robust to one odd step
  auto share = [&dt, base](int k) {
    const double centre = k * base;
    const auto n = std::count_if(
        dt.begin(), dt.end(), [centre](double d) { return std::abs(d - centre) <= 0.1 * centre; });
    return static_cast<double>(n) / static_cast<double>(dt.size());
  };
  const double at_base = share(1);
  int commoner = 0;
  for (int k = 2; k <= 8 && commoner == 0; ++k) commoner = share(k) > at_base ? k : 0;
  if (commoner == 0 && at_base >= 0.2) return {};
  return {
      true,
      run.label() +
          format(": irregular sample times (%.0f %% of intervals at the base step of %.2f ms",
                 100.0 * at_base, 1000.0 * base) +
          (commoner > 0
               ? format(", fewer than at %.0f times it; a DAQ's period is its commonest interval)",
                        commoner)
               : std::string(", a DAQ has most of its intervals there)"))};
}

SamplingCheck check_sampling(const std::vector<const PreparedRun*>& runs) {
  for (const PreparedRun* run : runs) {
    SamplingCheck c = check_sampling(*run->data);
    if (c.digitized) return c;
  }
  return {};
}

bool sampling_allows(const std::string& effect, const std::vector<const PreparedRun*>& runs,
                     std::string& why_not) {
  if (!rests_on_fine_structure(effect)) return true;
  const SamplingCheck c = check_sampling(runs);
  if (!c.digitized) return true;
  why_not = "digitized data (" + c.why +
            "): its fine structure is the digitizer's steps, not the instrument's or the tissue's";
  return false;
}

void append_sampling_warnings(const std::vector<const PreparedRun*>& runs,
                              std::vector<std::string>& warnings) {
  const SamplingCheck c = check_sampling(runs);
  if (!c.digitized) return;
  warnings.push_back("digitized sampling (" + c.why +
                     "): spatial_ripple, mains_interference and stick_slip are not applicable; the "
                     "noise floor is the digitizer's");
}

std::vector<std::string> base_misfit_warnings(const ForceModel& model, const Comparison& refitted) {
  std::vector<std::string> out;
  if (refitted.overall.r2 < kMinBaselineR2) {
    out.push_back(format("the model does not describe these data: refitted to them, Eq. 1 reaches "
                         "only R^2 = %.2f (cornea runs: above %.2f)",
                         refitted.overall.r2, kMinBaselineR2) +
                  "; it was made for ovine cornea under a keratome - refit or replace the base "
                  "model before reading effects on top of it");
  }
  const double lo = model.table.x_pi_mm.front(), hi = model.table.x_pi_mm.back();
  std::size_t unpunctured = 0, elsewhere = 0;
  std::string example;
  for (const RunComparison& run : refitted.runs) {
    const Segmentation& s = run.segmentation;
    if (!s.punctured) {
      ++unpunctured;
    } else if (s.x_pi_mm < 0.5 * lo || s.x_pi_mm > 2.0 * hi) {
      ++elsewhere;
      if (example.empty()) example = run.label + format(" at %.2f mm", s.x_pi_mm);
    }
  }
  const std::string of = " of " + std::to_string(refitted.runs.size()) + " run(s)";
  if (unpunctured > 0) {
    out.push_back(std::to_string(unpunctured) + of +
                  ": no puncture found - the keratome's phases (pre-cut, puncture, cutting, "
                  "unloading) do not match");
  }
  if (elsewhere > 0) {
    out.push_back(std::to_string(elsewhere) + of +
                  format(": puncture far from the model's %.2f-%.2f mm (Table 1), e.g. ", lo, hi) +
                  example + " - not the keratome's phases");
  }
  return out;
}

}  // namespace rig::model
