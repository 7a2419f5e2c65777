#pragma once
// One run in memory: what the run-CSV format carries (../shared/formats/run-csv.md) and
// what the model lab works on, whether it came from a file or from the archive.
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rig::model {

struct Channel {
  std::string name;            // column name, with its unit suffix (iop_meas_mmHg, ...)
  std::vector<double> values;  // one per sample
};

struct RunData {
  std::string source;                                     // file path or "archive run N"
  std::vector<std::pair<std::string, std::string>> meta;  // in file order, unknown keys kept
  std::vector<double> t_s;                                // seconds from the start of the run
  std::vector<double> x_mm;     // displacement from first contact, + into the eye
  std::vector<double> force_N;  // axial force, + pushing into the eye
  std::vector<Channel> channels;
  std::vector<std::string> warnings;

  std::size_t size() const { return t_s.size(); }
  std::optional<std::string> text(const std::string& key) const;
  // A metadata value that parses as a number (a numeric covariate), if present.
  std::optional<double> number(const std::string& key) const;
  void set(const std::string& key, const std::string& value);
  const Channel* channel(const std::string& name) const;
  // The first column or channel whose length is not size(), in words ("channel 'iop_meas_mmHg'
  // has 3 values for 5 samples"); the lab and the run-CSV writer index every channel by sample.
  std::optional<std::string> channel_length_mismatch() const;
  std::string label() const;  // eye id if known, else the source
};

}  // namespace rig::model
