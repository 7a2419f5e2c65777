#pragma once
// A run's camera frames, one file per run: a 16-byte header ("RIGFRAMES1" + padding), then
// the frames' pixels back to back; the archive's frame index holds each frame's offset,
// size, dimensions and sample. Appending only, so a crash leaves every indexed frame whole.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <string>

namespace rig::archive {

class FrameFile {
 public:
  explicit FrameFile(const std::string& path);  // creates or appends; throws naming the path
  // Appends one frame's pixels; returns its offset [B]. Throws on a write error (disk full).
  std::int64_t append(std::span<const std::uint8_t> pixels);
  void flush();  // to the disk (fdatasync)
  const std::string& path() const { return path_; }

 private:
  struct Closer {
    void operator()(std::FILE* f) const noexcept { std::fclose(f); }
  };
  std::string path_;
  std::unique_ptr<std::FILE, Closer> file_;
  std::int64_t size_ = 0;
};

}  // namespace rig::archive
