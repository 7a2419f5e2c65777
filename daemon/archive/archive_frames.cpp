// The archive's frame index: camera frames live in per-run files (FrameFile), the archive
// knows where each one is and which sample it belongs to.
#include "archive.hpp"

namespace rig::archive {

void Archive::add_frame(const FrameRow& f) {
  Statement q = db_.prepare(
      "INSERT INTO frames (run_id, frame_no, sample_index, camera_ts_ns, host_ts_ns, file, "
      "file_offset, bytes, width, height) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  q.bind(1, f.run_id)
      .bind(2, f.frame_no)
      .bind(3, f.sample_index)
      .bind(4, f.camera_ts_ns)
      .bind(5, f.host_ts_ns);
  q.bind(6, f.file).bind(7, f.file_offset).bind(8, f.bytes);
  q.bind(9, static_cast<std::int64_t>(f.width)).bind(10, static_cast<std::int64_t>(f.height));
  q.run();
}

std::vector<FrameRow> Archive::run_frames(std::int64_t run_id) {
  Statement q = db_.prepare(
      "SELECT frame_no, sample_index, camera_ts_ns, host_ts_ns, file, file_offset, bytes, width, "
      "height FROM frames "
      "WHERE run_id = ? ORDER BY frame_no");
  q.bind(1, run_id);
  std::vector<FrameRow> rows;
  while (q.step()) {
    FrameRow f;
    f.run_id = run_id;
    f.frame_no = q.integer(0);
    f.sample_index = q.integer(1);
    f.camera_ts_ns = q.integer(2);
    f.host_ts_ns = q.integer(3);
    f.file = q.text(4);
    f.file_offset = q.integer(5);
    f.bytes = q.integer(6);
    f.width = static_cast<int>(q.integer(7));
    f.height = static_cast<int>(q.integer(8));
    rows.push_back(std::move(f));
  }
  return rows;
}

}  // namespace rig::archive
