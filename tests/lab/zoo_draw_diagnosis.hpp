// One development draw of the blind zoo, diagnosed as the bench does (two worker threads,
// the paper's interpreted model as the base). Shared by the zoo's single-draw tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>

#include "diagnosis.hpp"
#include "zoo_scorer.hpp"

namespace rig::zoo {

// Draws `seed`, checks that the zoo still makes the effect the test was written for (a
// changed generator must fail the test, not silently test another effect), and diagnoses it.
inline model::Diagnosis diagnose_zoo_draw(std::uint64_t seed, const std::string& family,
                                          const std::string& form) {
  const ZooDraw draw = ZooGenerator().draw(seed);
  EXPECT_EQ(draw.family, family) << "seed " << seed;
  EXPECT_EQ(draw.form, form) << "seed " << seed;
  model::DiagnoseOptions options;
  options.threads = 2;
  return model::diagnose(model::ForceModel::paper_interpreted(), draw.runs, options);
}

// The candidate named `effect` in a diagnosis, or nullptr when it was not scored.
inline const model::CandidateResult* find_candidate(const model::Diagnosis& diagnosis,
                                                    const std::string& effect) {
  const auto it = std::find_if(diagnosis.candidates.begin(), diagnosis.candidates.end(),
                               [&](const model::CandidateResult& c) { return c.effect == effect; });
  return it == diagnosis.candidates.end() ? nullptr : &*it;
}

}  // namespace rig::zoo
