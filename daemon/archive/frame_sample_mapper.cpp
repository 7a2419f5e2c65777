#include "frame_sample_mapper.hpp"

#include <algorithm>
#include <cstdlib>

namespace rig::archive {

void FrameSampleMapper::on_trigger(std::int64_t sample_index, std::uint64_t host_ns) {
  std::lock_guard lock(mutex_);
  pending_.push_back({sample_index, host_ns, host_ns});
  constexpr std::size_t kMaxPending = 4096;  // a camera that never answers must not grow this
  if (pending_.size() > kMaxPending) pending_.pop_front(), ++lost_;
}

void FrameSampleMapper::on_trigger_acknowledged(std::int64_t sample_index, std::uint64_t host_ns) {
  std::lock_guard lock(mutex_);
  for (auto it = pending_.rbegin(); it != pending_.rend(); ++it) {
    if (it->sample_index != sample_index) continue;
    it->reached_by_ns = std::max(it->host_ns, host_ns);
    return;
  }
}

void FrameSampleMapper::drop_skipped_ids(std::uint64_t frame_id) {
  if (next_frame_id_ && frame_id > *next_frame_id_) {
    // The camera skipped ids: those frames' triggers will never be answered.
    for (std::uint64_t gap = frame_id - *next_frame_id_; gap > 0 && !pending_.empty(); --gap)
      pending_.pop_front(), ++lost_;
  }
  next_frame_id_ = frame_id + 1;
}

// Index into pending_ of the trigger this frame answers (pending_ holds at least one trigger
// raised before the arrival). The exposure on the host clock is estimated through the
// smallest (arrival - camera time) seen: that is the clock offset plus the fastest transfer,
// so the estimate falls just after the frame's own trigger (by that fastest transfer) and
// before the next one, however long this frame waited in queues. The frame answers the
// latest trigger that had reached the camera before the estimate. The first frame is the
// whole mapping so far: its estimate is its own arrival, which its transfer time may push past
// the next trigger; cameras answer triggers in order, so it answers the oldest one.
std::size_t FrameSampleMapper::answered_trigger(std::uint64_t camera_ns, std::uint64_t arrival_ns) {
  const auto offset = static_cast<std::int64_t>(arrival_ns) - static_cast<std::int64_t>(camera_ns);
  const bool first_timestamped_frame = !camera_to_host_ns_;
  if (first_timestamped_frame || offset < *camera_to_host_ns_) camera_to_host_ns_ = offset;
  if (first_timestamped_frame) return 0;
  const std::int64_t exposed_host_ns = static_cast<std::int64_t>(camera_ns) + *camera_to_host_ns_;
  std::size_t best = 0;
  for (std::size_t i = 1; i < pending_.size() &&
                          static_cast<std::int64_t>(pending_[i].reached_by_ns) <= exposed_host_ns;
       ++i)
    best = i;
  return best;
}

std::optional<std::int64_t> FrameSampleMapper::on_frame(std::uint64_t frame_id,
                                                        std::uint64_t camera_ns,
                                                        std::uint64_t arrival_ns) {
  std::lock_guard lock(mutex_);
  if (camera_ns == 0) drop_skipped_ids(frame_id);
  if (pending_.empty() || pending_.front().host_ns > arrival_ns) {
    ++untied_;
    return std::nullopt;
  }
  const std::size_t k = camera_ns == 0 ? 0 : answered_trigger(camera_ns, arrival_ns);
  const Trigger claimed = pending_[k];
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(k) + 1);
  lost_ += k;
  last_latency_ns_ = arrival_ns - claimed.host_ns;
  return claimed.sample_index;
}

void FrameSampleMapper::count_unanswered_triggers_as_lost() {
  std::lock_guard lock(mutex_);
  lost_ += pending_.size();
  pending_.clear();
}

std::uint64_t FrameSampleMapper::lost_frames() const {
  std::lock_guard lock(mutex_);
  return lost_;
}

std::uint64_t FrameSampleMapper::untied_frames() const {
  std::lock_guard lock(mutex_);
  return untied_;
}

std::uint64_t FrameSampleMapper::last_latency_ns() const {
  std::lock_guard lock(mutex_);
  return last_latency_ns_;
}

}  // namespace rig::archive
