#pragma once
// Writes a report (or any text output) so that a reader never sees an empty or partial file:
// into a temporary file beside the target, flushed, then renamed over it. On any failure
// the temporary file is removed, the target is left as it was, and the error names it.
#include <string>

namespace rig::model {

void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace rig::model
