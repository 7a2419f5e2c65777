#include "report_assets.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rig::model {
namespace {

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("report: cannot read " + path.string());
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

bool complete(const std::filesystem::path& root) {
  return std::filesystem::exists(root / "vendor" / "uPlot.iife.min.js") &&
         std::filesystem::exists(root / "vendor" / "uPlot.min.css") &&
         std::filesystem::exists(root / "lab_plots.js");
}

}  // namespace

std::vector<std::string> report_asset_places(const std::string& executable_dir) {
  std::vector<std::string> places;
  if (const char* root = std::getenv("RIG_WEB_ROOT"); root != nullptr && *root != '\0')
    places.emplace_back(root);
  const std::filesystem::path bin(executable_dir);
  places.push_back((bin / ".." / "web-root").lexically_normal().string());
  places.push_back((bin / ".." / "share" / "rigd" / "web").lexically_normal().string());
  places.emplace_back("/usr/share/rigd/web");
  return places;
}

ReportAssets find_report_assets(const std::string& executable_dir) {
  std::string looked;
  for (const std::string& place : report_asset_places(executable_dir)) {
    const std::filesystem::path root(place);
    if (complete(root)) {
      return {read_text(root / "vendor" / "uPlot.iife.min.js"),
              read_text(root / "vendor" / "uPlot.min.css"), read_text(root / "lab_plots.js"),
              place};
    }
    looked += (looked.empty() ? "" : ", ") + place;
  }
  throw std::runtime_error(
      "report: the page's assets (vendor/uPlot.iife.min.js, lab_plots.js) were not found in " +
      looked +
      "; build the target web_assets (./rig setup) or set RIG_WEB_ROOT to the page's directory");
}

}  // namespace rig::model
