// What a biomechanist expects from the meat-indentation data (tests/data/
// iaquinta2023-meat-indentation) beyond tests/lab/real_data_meat_test.cpp: a verdict that is
// tissue mechanics or "unexplained" with the excess in the holds, never an instrument, and a
// relaxation candidate that reads the decay the holds really show (43-51 % in 10 s). These
// depend on the effect families' fits and the verdict logic: label `lab`, release tree.
// Not asserted, because the lab does not do it yet (docs/model-lab.md, "Real data"): that
// stress_relaxation is significant - on top of a baseline that explains R^2 0.05-0.07 it gains
// only a few per cent - and that the best partial candidate is a tissue effect (it is no longer
// a ripple that does not repeat; sensor drift can still take the relaxation for a warm-up).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "diagnosis.hpp"
#include "phases.hpp"
#include "run_csv.hpp"
#include "test_paths.hpp"

namespace rig::model {
namespace {

std::vector<RunData> all_meat() {
  std::vector<RunData> runs;
  for (const char* file :
       {"230327-RDG15A-indent-6mm-hold.csv", "230327-FF1-1A-indent-6.8mm-hold.csv",
        "230331-FF2-2A-indent-to-1N-hold.csv", "230331-RDG1-1D-indent-to-1N-hold.csv"})
    runs.push_back(read_run_csv(
        testing::source(std::string("tests/data/iaquinta2023-meat-indentation/") + file)));
  return runs;
}

const CandidateResult* candidate(const Diagnosis& d, const std::string& name) {
  for (const auto& c : d.candidates) {
    if (c.effect == name) return &c;
  }
  return nullptr;
}

// The measured decay over the holds, pooled: 100 * (1 - sum of end forces / sum of start
// forces) [%].
double measured_hold_decay_pct(const std::vector<RunData>& runs) {
  double start = 0.0, end = 0.0;
  for (const RunData& run : runs) {
    const Segmentation s = detect_phases(run);
    start += run.force_N[s.hold_begin];
    end += run.force_N[s.hold_end - 1];
  }
  return 100.0 * (1.0 - end / start);
}

// The number after "decays by " in a candidate's evidence [%]; -1 if there is none.
double evidence_decay_pct(const std::string& evidence) {
  const std::string key = "decays by ";
  const auto at = evidence.find(key);
  return at == std::string::npos ? -1.0 : std::atof(evidence.c_str() + at + key.size());
}

class MeatDataBiomechanics : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    diagnosis_ = new Diagnosis(diagnose(ForceModel::paper_interpreted(), all_meat()));
    std::printf("meat: verdict %s, best partial candidate %s\n", diagnosis_->verdict.c_str(),
                diagnosis_->partial_candidate.c_str());
    for (const CandidateResult& c : diagnosis_->candidates)
      std::printf("meat:   %-18s applicable %d gain %6.1f %% significant %d: %s\n",
                  c.effect.c_str(), c.applicable, c.gain_pct, c.significant,
                  c.evidence.substr(0, 150).c_str());
  }
  static void TearDownTestSuite() {
    delete diagnosis_;
    diagnosis_ = nullptr;
  }
  static const Diagnosis& d() { return *diagnosis_; }

 private:
  static Diagnosis* diagnosis_;
};

Diagnosis* MeatDataBiomechanics::diagnosis_ = nullptr;

TEST_F(MeatDataBiomechanics, TheVerdictIsTissueMechanicsOrUnexplainedNeverAnInstrument) {
  for (const char* instrument :
       {"spatial_ripple", "mains_interference", "stick_slip", "sensor_drift"})
    EXPECT_NE(d().verdict, instrument);
  EXPECT_NE(d().verdict, "none") << "the residual is far above the floor on meat";
}

TEST_F(MeatDataBiomechanics, AnUnexplainedExcessIsPlacedInTheHolds) {
  if (d().verdict != "unexplained") {  // a named effect in these holds can only be the relaxation
    EXPECT_EQ(d().verdict, "stress_relaxation");
    return;
  }
  std::printf("meat: where: %s\n", d().unexplained_where.summary().c_str());
  double hold_share = 0.0;
  for (const ExcessBin& bin : d().unexplained_where.bins) {
    if (bin.view == "phase" && bin.bin == "hold") hold_share = bin.share;
  }
  EXPECT_GT(hold_share, 0.5) << d().unexplained_where.summary();
}

TEST_F(MeatDataBiomechanics, TheRelaxationCandidateReadsTheDecayTheHoldsShow) {
  const CandidateResult* relax = candidate(d(), "stress_relaxation");
  ASSERT_NE(relax, nullptr);
  ASSERT_TRUE(relax->applicable) << relax->not_applicable;
  const double measured = measured_hold_decay_pct(all_meat());
  const double read = evidence_decay_pct(relax->evidence);
  std::printf("meat: hold decay measured %.1f %%, read by stress_relaxation %.1f %%\n", measured,
              read);
  EXPECT_GT(measured, 40.0) << "the data: the meat relaxes to about half in 10 s";
  EXPECT_NEAR(read, measured, 10.0) << relax->evidence;
  EXPECT_NE(relax->where.find("hold"), std::string::npos)
      << "its fit changes the hold most: " << relax->where;
}

// A 3.9 mm "ripple" fitted over 6-8.4 mm ramps bends to Eq. 1's misfit; it repeats under 3
// times, so the lab must not offer it as the best partial candidate (it did before).
TEST_F(MeatDataBiomechanics, ARippleThatDoesNotRepeatOverTheRampsIsNotTheBestPartialCandidate) {
  EXPECT_NE(d().partial_candidate, "spatial_ripple");
  const CandidateResult* ripple = candidate(d(), "spatial_ripple");
  ASSERT_NE(ripple, nullptr);
  EXPECT_FALSE(ripple->applicable);
  EXPECT_NE(ripple->not_applicable.find("repeats only"), std::string::npos)
      << ripple->not_applicable;
}

}  // namespace
}  // namespace rig::model
