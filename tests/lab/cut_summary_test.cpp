// The demo's figures after a cut (model/lab/cut_summary.cpp): the velocity the rig held.
#include <gtest/gtest.h>

#include "cut_summary.hpp"

namespace rig::model {
namespace {

// A 1 kHz record of an insertion to 14 mm at velocity_mm_s; from stall_at_s on, the record
// has no sample for stall_ms and the blade did not move in it (the simulated world stopped).
RunData insertion(double velocity_mm_s, double stall_at_s, double stall_ms) {
  RunData run;
  run.source = "synthetic run";
  run.set("velocity_mm_s", "2.0");
  double t = 0.0, x = -1.0;
  while (x < 14.0) {
    run.t_s.push_back(t);
    run.x_mm.push_back(x);
    run.force_N.push_back(0.0);
    const bool stall_starts = t < stall_at_s && t + 0.001 >= stall_at_s;
    t += stall_starts ? stall_ms * 1e-3 : 0.001;
    x += velocity_mm_s * 0.001;
  }
  return run;
}

TEST(CutSummary, AStallOfTheWholeMachineIsAGapInTheRecordNotASlowCut) {
  const CutSummary s = summarize_cut(insertion(2.0, 3.0, 80.0), nullptr);
  EXPECT_NEAR(s.velocity_error_pct, 0.0, 0.01);
  EXPECT_NEAR(s.longest_gap_ms, 80.0, 0.01);
}

TEST(CutSummary, ACutThatIsSlowThroughoutIsReportedSlow) {
  const CutSummary s = summarize_cut(insertion(1.96, 3.0, 1.0), nullptr);
  EXPECT_NEAR(s.velocity_error_pct, -2.0, 0.01);
  EXPECT_NEAR(s.longest_gap_ms, 1.0, 0.01);
}

TEST(CutSummary, ARunWithoutAnInsertionIsRefusedNamingIt) {
  RunData run = insertion(2.0, 3.0, 1.0);
  run.x_mm.assign(run.x_mm.size(), 0.2);
  try {
    summarize_cut(run, nullptr);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("synthetic run"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rig::model
