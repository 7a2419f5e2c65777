#pragma once
// A catalogue entry that covers several forms of its physics (an effect family): the form
// is fixed per instance (the catalogue builds one per form and keeps the best by an
// information criterion, see form_selection.hpp). The evidence names the form and says so
// when a parameter never left its start or ended on a bound (a fit that did not converge),
// or when the runs give it nothing to act on (a parameter these runs cannot inform).
#include <string>
#include <utility>
#include <vector>

#include "effect_term.hpp"

namespace rig::model::effects {

// Unit of a shared parameter that only labels the form in a model file (forms without
// parameters of their own): the term never reads it, so it keeps its saved value.
inline constexpr const char* kFormLabelUnit = "form label";

class FamilyTerm : public EffectTerm {
 public:
  FamilyTerm(std::vector<std::string> form_names, int form);
  std::vector<std::string> forms() const override { return form_names_; }
  std::string form() const override { return form_names_[static_cast<std::size_t>(form_)]; }
  int form_index() const { return form_; }
  // How the form was chosen (e.g. "chosen by BIC over 4 forms; next viscous, dBIC 31").
  void set_selection_note(std::string note) { selection_note_ = std::move(note); }

 protected:
  // "; <selection note>; tau did not leave its start ..." (empty when all is well).
  std::string honesty(const EvidenceInput& in) const;
  // Why shared parameter k has no effect on these runs (e.g. "no stop on the way in"), or
  // empty: such a parameter stays at its start because nothing informs it, not because the
  // fit failed, and the evidence says that instead.
  virtual std::string uninformed_because(std::size_t /*k*/, const EvidenceInput& /*in*/) const {
    return {};
  }
  int form_;

 private:
  std::vector<std::string> form_names_;
  std::string selection_note_;
};

// The form whose index is `form` of `names`, or -1 if the name is unknown.
int form_named(const std::vector<std::string>& names, const std::string& form);

}  // namespace rig::model::effects
