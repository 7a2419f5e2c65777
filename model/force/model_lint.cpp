#include "model_lint.hpp"

#include <cmath>
#include <cstdio>
#include <set>

namespace rig::model {
namespace {

std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, format, a, b, c);
  return text;
}

void lint_printed(const ForceModel& m, std::vector<LintFinding>& out) {
  const PrintedParams& p = m.printed;
  if (p.names.size() != p.values.size()) {
    std::string missing;
    for (std::size_t i = p.values.size(); i < p.names.size(); ++i) missing += (missing.empty() ? "" : ", ") + p.names[i];
    out.push_back({LintFinding::Severity::kError,
                   std::to_string(p.names.size()) + " names but " + std::to_string(p.values.size()) +
                       " values: read positionally, " + missing + " has no value (taken as 0)"});
  }
  const std::set<std::string> used = {"a", "b", "c", "d", "e", "f", "g", "h", "m", "n"};
  for (const auto& name : p.names) {
    if (used.count(name) == 0U) out.push_back({LintFinding::Severity::kWarning, "parameter '" + name + "' is listed but Eq. 1 does not use it"});
  }
}

// Jump of the model at x: value just right minus value just left.
double jump_at(const ForceModel& m, double x, double iop) {
  constexpr double kEps = 1e-9;
  return m.baseline(x + kEps, iop) - m.baseline(x - kEps, iop);
}

}  // namespace

std::string to_string(LintFinding::Severity severity) {
  switch (severity) {
    case LintFinding::Severity::kError: return "error";
    case LintFinding::Severity::kWarning: return "warning";
    case LintFinding::Severity::kInfo: return "info";
  }
  return "?";
}

std::vector<LintFinding> lint_model(const ForceModel& m) {
  std::vector<LintFinding> out;
  if (m.form == ModelForm::kPrinted) lint_printed(m, out);
  constexpr double kTolerance_N = 1e-4;
  for (const double iop : m.table.iop_mmHg) {
    std::vector<std::pair<std::string, double>> joints;
    if (m.form == ModelForm::kPrinted) {
      joints = {{"toe end", m.printed.x_toe_end_mm}, {"x_pi", m.puncture_depth_mm(iop)},
                {"cut end", m.printed.x_cut_end_mm}, {"x_pf", m.final_depth_mm(iop)}};
    } else {
      joints = {{"toe end", m.params.x1}, {"x_pi", m.puncture_depth_mm(iop)},
                {"drop end", m.puncture_depth_mm(iop) + m.params.w_drop}, {"cut end", m.params.x_c},
                {"x_pf", m.final_depth_mm(iop)}};
    }
    for (const auto& [label, x] : joints) {
      const double size = jump_at(m, x, iop);
      if (std::abs(size) > kTolerance_N) {
        out.push_back({LintFinding::Severity::kError,
                       "discontinuity at " + label + fmt(" x = %.3f mm (IOP %.0f mmHg): jump %+.4f N", x, iop, size),
                       x, iop, size});
      }
    }
    if (m.baseline(m.final_depth_mm(iop) - 1e-6, iop) > kTolerance_N) {
      out.push_back({LintFinding::Severity::kWarning,
                     fmt("force does not reach zero at x_pf = %.3f mm (IOP %.0f mmHg): %.4f N just before it",
                         m.final_depth_mm(iop), iop, m.baseline(m.final_depth_mm(iop) - 1e-6, iop)),
                     m.final_depth_mm(iop), iop});
    }
  }
  for (std::size_t i = 0; i < m.table.iop_mmHg.size(); ++i) {
    if (m.table.x_pi_mm[i] >= m.table.x_pf_mm[i]) out.push_back({LintFinding::Severity::kError, fmt("x_pi >= x_pf at IOP %.1f", m.table.iop_mmHg[i])});
  }
  out.push_back({LintFinding::Severity::kInfo, fmt("IOP table covers %.1f..%.1f mmHg; outside it x_pi and x_pf are extrapolated (a warning)",
                                                   m.table.iop_mmHg.front(), m.table.iop_mmHg.back())});
  return out;
}

}  // namespace rig::model
