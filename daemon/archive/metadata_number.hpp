#pragma once
// A numeric metadata column (IOP, velocity, depth, hold, post-mortem time) as text: the one
// spelling that the local archive, the lab archive's reader and run-CSV exports all give, so a
// run read back from either archive has the same metadata text (10 significant digits).
#include <sstream>
#include <string>

namespace rig::archive {

inline std::string metadata_number_text(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

}  // namespace rig::archive
