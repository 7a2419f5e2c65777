#include "run_loader.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "archive.hpp"
#include "lab_source.hpp"
#include "run_csv.hpp"

namespace rig::cli {

std::string executable_dir() {
  std::error_code ec;
  return std::filesystem::read_symlink("/proc/self/exe", ec).parent_path().string();
}

std::vector<model::RunData> load_runs(const std::vector<std::string>& paths,
                                      const std::string& archive_path) {
  std::vector<model::RunData> runs;
  std::unique_ptr<archive::Archive> archive;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::string& path = paths[i];
    if (is_lab_source(path)) {
      for (auto& run : load_lab_runs(parse_lab_source(paths, i))) runs.push_back(std::move(run));
      continue;
    }
    const bool run_id = !path.empty() && std::all_of(path.begin(), path.end(), ::isdigit);
    if (run_id && !std::filesystem::exists(path)) {
      if (!archive) archive = std::make_unique<archive::Archive>(archive_path, true);
      runs.push_back(archive->load_run(std::stoll(path)));
    } else if (std::filesystem::is_directory(path)) {
      std::vector<std::string> files;
      for (const auto& entry : std::filesystem::directory_iterator(path)) {
        if (entry.path().extension() == ".csv") files.push_back(entry.path().string());
      }
      std::sort(files.begin(), files.end());
      if (files.empty()) throw std::runtime_error(path + ": no .csv files in this folder");
      for (const auto& file : files) runs.push_back(model::read_run_csv(file));
    } else if (std::filesystem::exists(path)) {
      runs.push_back(model::read_run_csv(path));
    } else {
      throw std::runtime_error(path + ": no such file, folder or archive run");
    }
  }
  if (runs.empty()) throw std::runtime_error("no runs given");
  for (const auto& run : runs) {
    for (const auto& warning : run.warnings) std::cerr << "warning: " << warning << "\n";
  }
  return runs;
}

std::string default_model_file(const std::string& given) {
  if (!given.empty()) return given;
  std::vector<std::filesystem::path> places;
  if (const char* dir = std::getenv("RIG_MODEL_DIR")) places.emplace_back(dir);
  places.emplace_back(std::filesystem::path(executable_dir()) / ".." / "share" / "rigd" / "models");
  places.emplace_back("/usr/share/rigd/models");
  places.emplace_back(RIG_SOURCE_MODEL_DIR);
  for (const auto& dir : places) {
    if (std::filesystem::exists(dir / "paper-interpreted.toml"))
      return (dir / "paper-interpreted.toml").lexically_normal().string();
  }
  throw std::runtime_error(
      "no model file given and paper-interpreted.toml not found; use --model FILE");
}

}  // namespace rig::cli
