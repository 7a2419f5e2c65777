#pragma once
// Eye variation that follows a run variable is not eye variation. Each eye is cut at one speed
// and IOP with one value of every covariate, so a puncture that moves with post_mortem_h, or a
// cut that scales with speed, fits as "eyes differ": the floor then holds the effect (zoo
// draws 160009, 170031, 170046: a lab floor 3-5x the true one). This names the suspect.
#include <string>
#include <vector>

#include "eye_params.hpp"
#include "prepared_run.hpp"

namespace rig::model {

// Warnings for each eye parameter (puncture depth, pre-cut and cutting scale) whose per-run
// values correlate with the speed, the IOP or a covariate at |r| >= 0.9 over 6 or more runs.
std::vector<std::string> eye_confound_warnings(const std::vector<const PreparedRun*>& runs, const std::vector<EyeParams>& eyes,
                                               const std::vector<std::string>& covariate_keys);

}  // namespace rig::model
