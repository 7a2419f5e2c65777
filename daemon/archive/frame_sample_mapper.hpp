#pragma once
// Ties each camera frame to the sample (loop cycle) at which its exposure was triggered.
// The loop raises the trigger at a known cycle; the frame arrives later, possibly after the
// next trigger (latency is not bounded by the trigger period), and a camera may merge two
// close triggers into one frame. So the pairing uses the camera's own timestamp of the
// exposure, mapped to the host clock through the smallest (arrival - camera time) seen so
// far: the frame answers the latest trigger raised before that estimate; older pending
// triggers got no frame (lost). The first frame calibrates the mapping and has no estimate
// of its own: it answers the oldest pending trigger, as cameras answer in order. The next
// frames refine the mapping: one that waited in a queue longer than a trigger period before
// any prompt frame was seen can be tied one trigger late. Without camera timestamps (0), frames and
// triggers pair in order and a gap in the camera's frame ids drops as many triggers. A frame that
// arrives before any pending trigger was raised is not tied to a sample. A software trigger is a
// command the camera acknowledges: it reached the camera between its raise and its acknowledgement.
// When the host stalls between the two (a loaded machine), the raise time says too little: the next
// trigger's raise can precede this trigger's exposure. So a trigger whose acknowledgement is
// reported is judged by that later time when deciding which trigger a frame answers.
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

namespace rig::archive {

class FrameSampleMapper {
 public:
  void on_trigger(std::int64_t sample_index, std::uint64_t host_ns);
  // The camera acknowledged the trigger raised at sample_index at host_ns [ns,
  // CLOCK_MONOTONIC]; a trigger already answered (or never raised) is ignored.
  void on_trigger_acknowledged(std::int64_t sample_index, std::uint64_t host_ns);
  // frame_id: the camera's frame/block counter; camera_ns: its exposure timestamp (0 if it
  // has none); arrival [ns, CLOCK_MONOTONIC].
  std::optional<std::int64_t> on_frame(std::uint64_t frame_id, std::uint64_t camera_ns,
                                       std::uint64_t arrival_ns);
  // The run is over and no more frames will be read: the triggers still waiting for a frame
  // never got one and are counted lost (a camera that merged or dropped the run's last
  // triggers must show in lost_frames(), not vanish).
  void count_unanswered_triggers_as_lost();
  std::uint64_t lost_frames() const;    // triggers that never got a frame
  std::uint64_t untied_frames() const;  // frames with no trigger before them
  // Latency of the last tied frame, trigger to arrival [ns].
  std::uint64_t last_latency_ns() const;

 private:
  struct Trigger {
    std::int64_t sample_index;
    std::uint64_t host_ns;        // raised [ns]
    std::uint64_t reached_by_ns;  // reached the camera by then [ns]: its ack, or host_ns
  };
  mutable std::mutex mutex_;  // triggers and frames come from different threads (never the RT one)
  std::deque<Trigger> pending_;
  std::uint64_t lost_ = 0, untied_ = 0, last_latency_ns_ = 0;
  std::optional<std::uint64_t> next_frame_id_;
  std::optional<std::int64_t> camera_to_host_ns_;  // min(arrival - camera time) so far
  void drop_skipped_ids(std::uint64_t frame_id);
  std::size_t answered_trigger(std::uint64_t camera_ns, std::uint64_t arrival_ns);
};

}  // namespace rig::archive
