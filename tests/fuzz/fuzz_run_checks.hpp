#pragma once
// Shared by the targets that read runs back (archive rows, lab archive rows): what a reader
// may do with bad data, and what run data it hands on must satisfy.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "run_csv.hpp"
#include "run_data.hpp"

namespace rig::fuzz {

[[noreturn]] inline void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "FUZZ FINDING: %s: %s\n", what, detail.substr(0, 300).c_str());
  std::abort();
}

// A reader may refuse, with a message (a runtime_error); any other way out is a finding.
inline void refusal_allowed(const std::string& what, const std::function<void()>& read) {
  try {
    read();
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).empty()) finding("a refusal without a message", what);
  } catch (const std::exception& e) {
    finding("an exception that is not a refusal", what + ": " + e.what());
  }
}

// Every column and channel has one value per sample: the lab and the run-CSV writer index
// them all by sample.
inline void check_columns(const model::RunData& run, const std::string& what) {
  if (run.x_mm.size() != run.size() || run.force_N.size() != run.size())
    finding("columns of different lengths", what);
  for (const auto& channel : run.channels) {
    if (channel.values.size() != run.size())
      finding("a channel of another length than the samples", what + ": " + channel.name);
  }
}

// The run as `rig export --csv` writes it, and the run-CSV reader on what was written.
inline void export_and_read_back(const model::RunData& run, const std::string& what) {
  std::ostringstream csv;
  model::write_run_csv(run, csv);
  std::istringstream back(csv.str());
  refusal_allowed(what + " read back", [&back] { (void)model::read_run_csv(back, "export.csv"); });
}

}  // namespace rig::fuzz
