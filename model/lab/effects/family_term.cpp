#include "family_term.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rig::model::effects {

FamilyTerm::FamilyTerm(std::vector<std::string> form_names, int form)
    : form_(form), form_names_(std::move(form_names)) {
  if (form_ < 0 || form_ >= static_cast<int>(form_names_.size()))
    throw std::invalid_argument("effect form index out of range");
}

std::string FamilyTerm::honesty(const EvidenceInput& in) const {
  std::string text;
  if (!selection_note_.empty()) text += "; " + selection_note_;
  const auto specs = shared_params();
  const auto start_points = starts();
  for (std::size_t k = 0; k < specs.size(); ++k) {
    if (specs[k].unit == kFormLabelUnit) continue;  // a label of the form, never fitted
    const double value = in.shared[k];
    const double span = std::max(specs[k].upper - specs[k].lower, 1e-12);
    const bool at_start =
        std::any_of(start_points.begin(), start_points.end(), [&](const std::vector<double>& s) {
          return k < s.size() && std::abs(s[k] - value) <= 1e-9 * span;
        });
    const bool at_bound = std::min(value - specs[k].lower, specs[k].upper - value) <= 1e-4 * span;
    const std::string uninformed = at_start ? uninformed_because(k, in) : std::string();
    if (!uninformed.empty()) {
      text += "; " + specs[k].name + " has nothing to act on in these runs (" + uninformed +
              "): left at its start value";
    } else if (at_start) {
      text +=
          "; " + specs[k].name +
          " did not leave its start value (the fit did not converge: not identified by these runs)";
    } else if (at_bound) {
      text += "; " + specs[k].name +
              " ended on its bound (the fit did not converge inside the allowed range)";
    }
  }
  return text;
}

int form_named(const std::vector<std::string>& names, const std::string& form) {
  const auto at = std::find(names.begin(), names.end(), form);
  return at == names.end() ? -1 : static_cast<int>(at - names.begin());
}

}  // namespace rig::model::effects
