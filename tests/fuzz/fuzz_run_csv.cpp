// libFuzzer target: the run-CSV reader (shared/formats/run-csv.md). Any input either parses
// or is refused with an exception that names the problem; nothing else may happen
// (ASan/UBSan abort on memory errors and undefined behaviour).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "run_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const rig::model::RunData run = rig::model::read_run_csv(in, "fuzz.csv");
    if (run.t_s.size() != run.x_mm.size() || run.t_s.size() != run.force_N.size())
      __builtin_trap();  // columns must agree
  } catch (const std::runtime_error&) {
    // refused with a message: fine
  }
  return 0;
}
