#include "model_lint.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "number_text.hpp"

namespace rig::model {
namespace {

std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0) {
  return number_text(format, a, b, c);
}

void lint_printed(const ForceModel& m, std::vector<LintFinding>& out) {
  const PrintedParams& p = m.printed;
  if (p.names.size() != p.values.size()) {
    std::string missing;
    for (std::size_t i = p.values.size(); i < p.names.size(); ++i)
      missing += (missing.empty() ? "" : ", ") + p.names[i];
    out.push_back({LintFinding::Severity::kError, std::to_string(p.names.size()) + " names but " +
                                                      std::to_string(p.values.size()) +
                                                      " values: read positionally, " + missing +
                                                      " has no value (taken as 0)"});
  }
  const std::set<std::string> used = {"a", "b", "c", "d", "e", "f", "g", "h", "m", "n"};
  for (const auto& name : p.names) {
    if (used.count(name) == 0U)
      out.push_back({LintFinding::Severity::kWarning,
                     "parameter '" + name + "' is listed but Eq. 1 does not use it"});
  }
}

// Jump of the model at x: value just right minus value just left.
double jump_at(const ForceModel& m, double x, double iop) {
  constexpr double kEps = 1e-9;
  return m.baseline(x + kEps, iop) - m.baseline(x - kEps, iop);
}

// Where a piece of the model goes below zero: a keratome pushing into the eye is never
// pulled by it, so a negative force is a defect (the printed unloading piece, read
// positionally, is -0.53 N at 6.89 mm).
void lint_negative(const ForceModel& m, double iop, std::vector<LintFinding>& out) {
  constexpr double kTolerance_N = 1e-4;
  const double end = m.final_depth_mm(iop);
  double worst = 0.0, worst_x = 0.0, first_x = -1.0, last_x = 0.0;
  const double step_mm = std::max(0.01, end / 20000.0);  // at most 20,000 points per IOP row
  for (double x = step_mm; x < end; x += step_mm) {
    const double f = m.baseline(x, iop);
    if (f >= -kTolerance_N) continue;
    if (first_x < 0.0) first_x = x;
    last_x = x;
    if (f < worst) worst = f, worst_x = x;
  }
  if (first_x < 0.0) return;
  out.push_back({LintFinding::Severity::kError,
                 fmt("negative force from x = %.2f to %.2f mm", first_x, last_x) +
                     fmt(" (IOP %.0f mmHg), down to %.4f N", iop, worst) +
                     fmt(" at x = %.2f mm: the blade would be pulled into the eye", worst_x),
                 worst_x, iop, 0.0, worst});
}

// The reading without the stray k, beside the positional one: what its unloading piece does.
void suggest_reading_without_k(const ForceModel& m, std::vector<LintFinding>& out) {
  const std::optional<ForceModel> alt = reading_without_k(m);
  if (!alt) return;
  const double iop = m.table.iop_mmHg.front(), xc = m.printed.x_cut_end_mm,
               xpf = alt->final_depth_mm(iop);
  out.push_back(
      {LintFinding::Severity::kInfo,
       "reading without the stray k (" + std::to_string(alt->printed.names.size()) + " names, " +
           std::to_string(alt->printed.values.size()) +
           " values; model/params/paper-printed-without-k.toml): " +
           fmt("h = %g, m = %g, ", alt->printed.value("h"), alt->printed.value("m")) +
           fmt("n = %g; ", alt->printed.value("n")) +
           fmt("at IOP %.0f mmHg unloading runs %+.4f N", iop, alt->baseline(xc + 1e-6, iop)) +
           fmt(" at %.2f mm to %+.4f N", xc, alt->baseline(xpf - 1e-6, iop)) +
           fmt(" at x_pf = %.2f mm (the positional reading: %+.4f N", xpf,
               m.baseline(xc + 1e-6, iop)) +
           fmt(" to %+.4f N)", m.baseline(xpf - 1e-6, iop))});
}

}  // namespace

std::optional<ForceModel> reading_without_k(const ForceModel& printed) {
  const PrintedParams& p = printed.printed;
  if (printed.form != ModelForm::kPrinted || p.names.size() != p.values.size() + 1)
    return std::nullopt;
  ForceModel alt = printed;
  auto& names = alt.printed.names;
  const auto k = std::find(names.begin(), names.end(), "k");
  if (k == names.end()) return std::nullopt;
  names.erase(k);
  alt.name = printed.name + "-without-k";
  return alt;
}

std::string printed_form_warning(const ForceModel& model) {
  return "model '" + model.name + "' (" + model.path +
         ") is Eq. 1 exactly as printed (form eq1-printed) and is evaluated as printed: " +
         "it jumps at 0.75 mm, x_pi, 6.89 mm and x_pf and its unloading piece may be negative "
         "(`rig model lint " +
         model.path + "` lists every defect); the lab's reading is paper-interpreted.toml";
}

std::string printed_form_refusal(const ForceModel& model, const std::string& what) {
  return model.path + ": '" + model.name + "' is Eq. 1 as printed (form eq1-printed); " + what +
         " needs the continuous reading, whose parameters the lab fits: use paper-interpreted.toml "
         "(docs/model.md), " +
         "or `rig model compare --model " + model.path +
         "` to see the printed form against data as printed";
}

std::string to_string(LintFinding::Severity severity) {
  switch (severity) {
    case LintFinding::Severity::kError:
      return "error";
    case LintFinding::Severity::kWarning:
      return "warning";
    case LintFinding::Severity::kInfo:
      return "info";
  }
  return "?";
}

std::vector<LintFinding> lint_model(const ForceModel& m) {
  std::vector<LintFinding> out;
  if (m.form == ModelForm::kPrinted) lint_printed(m, out);
  if (m.form == ModelForm::kPrinted) suggest_reading_without_k(m, out);
  constexpr double kTolerance_N = 1e-4;
  for (const double iop : m.table.iop_mmHg) {
    std::vector<std::pair<std::string, double>> joints;
    if (m.form == ModelForm::kPrinted) {
      joints = {{"toe end", m.printed.x_toe_end_mm},
                {"x_pi", m.puncture_depth_mm(iop)},
                {"cut end", m.printed.x_cut_end_mm},
                {"x_pf", m.final_depth_mm(iop)}};
    } else {
      joints = {{"toe end", m.params.x1},
                {"x_pi", m.puncture_depth_mm(iop)},
                {"drop end", m.puncture_depth_mm(iop) + m.params.w_drop},
                {"cut end", m.params.x_c},
                {"x_pf", m.final_depth_mm(iop)}};
    }
    for (const auto& [label, x] : joints) {
      const double size = jump_at(m, x, iop);
      if (std::abs(size) > kTolerance_N) {
        out.push_back({LintFinding::Severity::kError,
                       "discontinuity at " + label +
                           fmt(" x = %.3f mm (IOP %.0f mmHg): jump %+.4f N", x, iop, size),
                       x, iop, size});
      }
    }
    lint_negative(m, iop, out);
    if (m.baseline(m.final_depth_mm(iop) - 1e-6, iop) > kTolerance_N) {
      out.push_back(
          {LintFinding::Severity::kWarning,
           fmt("force does not reach zero at x_pf = %.3f mm (IOP %.0f mmHg): %.4f N just before it",
               m.final_depth_mm(iop), iop, m.baseline(m.final_depth_mm(iop) - 1e-6, iop)),
           m.final_depth_mm(iop), iop});
    }
  }
  for (std::size_t i = 0; i < m.table.iop_mmHg.size(); ++i) {
    if (m.table.x_pi_mm[i] >= m.table.x_pf_mm[i])
      out.push_back(
          {LintFinding::Severity::kError, fmt("x_pi >= x_pf at IOP %.1f", m.table.iop_mmHg[i])});
  }
  out.push_back(
      {LintFinding::Severity::kInfo, fmt("IOP table covers %.1f..%.1f mmHg; outside it x_pi and "
                                         "x_pf are extrapolated (a warning)",
                                         m.table.iop_mmHg.front(), m.table.iop_mmHg.back())});
  return out;
}

}  // namespace rig::model
