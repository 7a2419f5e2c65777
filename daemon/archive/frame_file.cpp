#include "frame_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace rig::archive {
namespace {
constexpr char kMagic[16] = "RIGFRAMES1\n";
}

FrameFile::FrameFile(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "ab")) {
  if (!file_) throw std::runtime_error("frame file " + path + ": " + std::strerror(errno));
  std::fseek(file_.get(), 0, SEEK_END);
  size_ = std::ftell(file_.get());
  if (size_ == 0) {
    if (std::fwrite(kMagic, 1, sizeof kMagic, file_.get()) != sizeof kMagic) {
      throw std::runtime_error("frame file " + path +
                               ": cannot write the header: " + std::strerror(errno));
    }
    size_ = sizeof kMagic;
  }
}

std::int64_t FrameFile::append(std::span<const std::uint8_t> pixels) {
  const std::int64_t offset = size_;
  if (std::fwrite(pixels.data(), 1, pixels.size(), file_.get()) != pixels.size() ||
      std::fflush(file_.get()) != 0) {
    throw std::runtime_error("frame file " + path_ + ": write failed: " + std::strerror(errno));
  }
  size_ += static_cast<std::int64_t>(pixels.size());
  return offset;
}

void FrameFile::flush() {
  std::fflush(file_.get());
  fdatasync(fileno(file_.get()));
}

}  // namespace rig::archive
