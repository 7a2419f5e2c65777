#pragma once
// The page's view of runs in the lab's PostgreSQL archive (docs/lab-archive.md): the run list
// with the filters `rig runs pg:` takes, and one run's samples in the same form as a local
// run's replay (run_replay.hpp, proto RunStream), so the Live tab's run picker shows a run
// of any rig of the lab as it shows its own.
#include <memory>
#include <string>
#include <vector>

#include "force_model.hpp"
#include "run_replay.hpp"

namespace rig::lab_archive {
class LabRunReader;
}

namespace rig::api {

// The query string of GET /api/lab-archive/runs: rig=R, eye_lot=L, since=D, any other
// key=value a metadata filter (percent-decoded). Throws std::invalid_argument naming the
// field when a pair is not key=value.
std::vector<std::string> parse_lab_run_filters(const std::string& target);

// {"runs": [...]} newest last, at most `newest` of them (the picker's list).
std::string lab_run_list_json(lab_archive::LabRunReader& reader,
                              const std::vector<std::string>& filters, std::size_t newest);

// The run's samples from the query's sample index on, its events; no camera frames (the lab
// archive keeps their index, not their pixels). Throws std::out_of_range if there is no such
// run, std::invalid_argument if run_uuid is not a UUID.
std::string lab_run_stream_json(lab_archive::LabRunReader& reader, const std::string& run_uuid,
                                const ReplayQuery& query,
                                const std::shared_ptr<const model::ForceModel>& model);

}  // namespace rig::api
