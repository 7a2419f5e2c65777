#pragma once
// Keeps this machine busy the way a lab PC or a CI runner is, for as long as the object
// lives: one spinning process per core, a parallel build (one compiler per core, again and
// again) and a writer forcing data to disk (all SCHED_OTHER). A browser on a page is started
// per cut by the load tests themselves (browser_on_page()).
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "test_paths.hpp"

namespace rig::testing {

class BusyMachine {
 public:
  explicit BusyMachine(const ScratchDir& dir) {
    const unsigned cores = std::max(1U, std::thread::hardware_concurrency());
    for (unsigned i = 0; i < cores; ++i) {
      load_.push_back(std::make_unique<cli::ChildProcess>(
          std::vector<std::string>{"/bin/sh", "-c", "while :; do :; done"},
          dir.file("hog-" + std::to_string(i) + ".log")));
    }
    // The compiler's own heavy headers (<regex>, <iostream>, ranges): a second or two of cc1plus
    // per round, its memory and page faults like a real build's.
    const std::string source = dir.file("busy-build.cpp");
    std::ofstream(source)
        << "#include <regex>\n#include <iostream>\n#include <map>\n#include <ranges>\n"
           "int main(int n, char** a) { std::map<std::string, std::regex> m; m[a[0]] = "
           "std::regex(\"[a-z]+\");\n"
           "  for (int v : std::views::iota(0, n)) std::cout << v << std::regex_match(a[0], "
           "m[a[0]]); }\n";
    for (unsigned i = 0; i < cores; ++i) {
      const std::string compile = "while :; do c++ -std=c++20 -O2 -c " + source + " -o " +
                                  dir.file("busy-build-" + std::to_string(i) + ".o") +
                                  " || sleep 1; done";
      load_.push_back(
          std::make_unique<cli::ChildProcess>(std::vector<std::string>{"/bin/sh", "-c", compile},
                                              dir.file("build-" + std::to_string(i) + ".log")));
    }
    const std::string writer = "while :; do dd if=/dev/zero of=" + dir.file("busy-io") +
                               " bs=64k count=256 oflag=dsync status=none || sleep 1; done";
    load_.push_back(std::make_unique<cli::ChildProcess>(
        std::vector<std::string>{"/bin/sh", "-c", writer}, dir.file("writer.log")));
  }

  // Headless Chromium showing `url` (the live overlay: WebSocket streams, camera frames).
  static std::unique_ptr<cli::ChildProcess> browser_on_page(const ScratchDir& dir,
                                                            const std::string& url,
                                                            const std::string& name) {
    return std::make_unique<cli::ChildProcess>(
        std::vector<std::string>{"/usr/bin/chromium", "--headless=new", "--no-sandbox",
                                 "--disable-gpu", "--no-first-run",
                                 "--user-data-dir=" + dir.file("chromium-" + name), url},
        dir.file("chromium-" + name + ".log"));
  }

 private:
  std::vector<std::unique_ptr<cli::ChildProcess>> load_;
};

}  // namespace rig::testing
