#pragma once
// The page's view of an archived (or still recording) run: every sample from a loop cycle
// on, with the model's force and the residual as the live stream has them, the run's events
// and the camera frames tied to samples. The page fetches the run from its start, then
// follows the live stream by cycle (sequence number) without gaps or duplicates.
#include <cstdint>
#include <memory>
#include <string>

#include "archive.hpp"
#include "force_model.hpp"

namespace rig::api {

struct ReplayQuery {
  std::int64_t from_cycle = 0;  // first loop cycle wanted
  // Samples at most in one answer (50 s at 1 kHz); the page asks again from next_cycle.
  std::int64_t limit = 50000;
};

// Reads ?from=N&limit=M of a request target; throws std::invalid_argument naming the field.
ReplayQuery parse_replay_query(const std::string& target);

// The run's samples from the query's cycle as JSON (proto RunStream). archive: the open
// archive (samples, events, frames); model may be null (model and residual are then null).
std::string run_stream_json(archive::Archive& archive, std::int64_t run_id,
                            const ReplayQuery& query,
                            const std::shared_ptr<const model::ForceModel>& model);

// One archived camera frame's pixels (8-bit grey, row-major) and its size; throws
// std::out_of_range if the run has no such frame.
struct FramePixels {
  int width = 0, height = 0;
  std::int64_t sample_index = -1;
  std::string pixels;
};
FramePixels read_archived_frame(archive::Archive& archive, std::int64_t run_id,
                                std::int64_t frame_no);

}  // namespace rig::api
