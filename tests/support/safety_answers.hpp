#pragma once
// Stop and e-stop replies judged against issue 14's bound, each one (not a median).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "http_probe.hpp"

namespace rig::testing {

inline constexpr double kSafetyAnswerBound_ms =
    100.0;  // issue 14: stop / e-stop answered within this

// Every reply 200 within the bound, each one (not a median), counted from the established
// connection: its connect is the kernel's and this client's (on a 2-core VM shared with
// builds, a loopback connect alone once took 2 s: the test's own thread waited for a CPU).
// Prints median and worst of both.
inline void expect_each_answered_in_time(const std::vector<ProbeReply>& replies,
                                         const std::string& what) {
  std::vector<double> answer_ms;
  std::vector<double> connect_ms;
  for (std::size_t i = 0; i < replies.size(); ++i) {
    const ProbeReply& r = replies[i];
    EXPECT_EQ(r.status, 200) << what << " #" << i << ": " << r.error << r.body;
    EXPECT_LT(r.took_ms - r.connected_ms, kSafetyAnswerBound_ms)
        << what << " #" << i << " answer time after connecting [ms] (connect: " << r.connected_ms
        << " ms)";
    answer_ms.push_back(r.took_ms - r.connected_ms);
    connect_ms.push_back(r.connected_ms);
  }
  std::sort(answer_ms.begin(), answer_ms.end());
  std::sort(connect_ms.begin(), connect_ms.end());
  if (answer_ms.empty()) return;
  std::printf(
      "%s: %zu answered, median %.1f ms, worst %.1f ms (connect: median %.1f, worst %.1f)\n",
      what.c_str(), answer_ms.size(), answer_ms[answer_ms.size() / 2], answer_ms.back(),
      connect_ms[connect_ms.size() / 2], connect_ms.back());
}

}  // namespace rig::testing
