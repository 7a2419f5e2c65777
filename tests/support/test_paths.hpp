#pragma once
// Where the tests find the project's binaries, sources and a scratch directory.
#include <unistd.h>
#include <filesystem>
#include <string>

namespace rig::testing {

inline std::string bin(const std::string& name) {
  return std::string(RIG_TEST_BIN_DIR) + "/" + name;
}
inline std::string source(const std::string& relative) {
  return std::string(RIG_SOURCE_DIR) + "/" + relative;
}
inline std::string shared_dir(const std::string& relative) {
  return std::string(RIG_SOURCE_DIR) + "/../shared/" + relative;
}

// A fresh directory per test, removed at the end unless RIG_KEEP_TEST_DIRS is set.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name) {
    path_ = std::filesystem::temp_directory_path() /
            ("rigtest-" + name + "-" + std::to_string(getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  // Never throws: a process the test started may still be writing into the folder while it
  // goes (the load tier's background build did, and the throw ended the test with abort()
  // before its figures were flushed). Tried again briefly; what is left stays in /tmp.
  ~ScratchDir() {
    if (std::getenv("RIG_KEEP_TEST_DIRS") != nullptr) return;
    std::error_code error;
    for (int attempt = 0; attempt < 20; ++attempt) {
      error.clear();
      std::filesystem::remove_all(path_, error);
      if (!error) return;
      usleep(100'000);  // [us]
    }
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace rig::testing
