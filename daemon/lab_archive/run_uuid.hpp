#pragma once
// The lab-wide identity of a run: a UUID derived from the rig id, the local run id and the
// run's creation time (ms). Deterministic, so a rigd that restarts, or a replay of a lost
// transfer, names the run the same way and never creates a second copy; a recreated local
// archive (ids start at 1 again) gives new UUIDs because the creation times differ.
#include <cstdint>
#include <string>

namespace rig::lab_archive {

std::string lab_run_uuid(const std::string& rig_id, std::int64_t local_run_id,
                         const std::string& created_at);

}  // namespace rig::lab_archive
