#pragma once
// Reader and writer of the run-CSV interchange format. A row that cannot be parsed is an
// error naming the file and line; nothing is silently skipped.
#include <istream>
#include <ostream>
#include <stdexcept>
#include <string>

#include "run_data.hpp"

namespace rig::model {

class RunCsvError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

RunData read_run_csv(const std::string& path);
RunData read_run_csv(std::istream& in, const std::string& name);
void write_run_csv(const RunData& run, std::ostream& out);
void write_run_csv(const RunData& run, const std::string& path);

}  // namespace rig::model
