// Tearing whose period grows along the cut in the blind zoo (a development draw), diagnosed as
// the bench does. Part of test_lab_zoo (label lab, release tree): one diagnosis, ~60 s optimised.
#include <gtest/gtest.h>

#include <string>

#include "zoo_draw_diagnosis.hpp"

namespace rig::zoo {
namespace {

// Seed 390016 (scored in the blind range 390000-390029, a development draw since 2026-12-07)
// tears with a period that grows linearly with depth, 7.7x its floor. No periodic form of the
// lab had a period that changes along the cut, and the released-tears form finds no releases
// in a smooth pattern: `unexplained`, `stick_slip` ranked first. The family's fifth form (the
// period p exp(g d), each eye its own amplitude and phase) is not the simulator's law
// (SimulatedForms.TearingThatGrowsAlongTheCutIsNotTheLabsExponentialPeriod) and names it.
TEST(BlindZoo, TearingWhosePeriodGrowsAlongTheCutIsNamedWithAPeriodThatChanges) {
  const model::Diagnosis d = diagnose_zoo_draw(390016, "stick_slip", "stick_slip:growing");
  EXPECT_EQ(d.verdict, "stick_slip");
  const model::CandidateResult* tearing = find_candidate(d, "stick_slip");
  ASSERT_NE(tearing, nullptr);
  EXPECT_NE(tearing->evidence.find("period changes along the cut"), std::string::npos)
      << tearing->evidence;
  EXPECT_GT(tearing->gain_pct, 40.0);
}

}  // namespace
}  // namespace rig::zoo
