// libFuzzer target: rows read back from the SQLite run archive (issue 14). The bytes become
// the rows of a real archive file with the product's schema (runs, run_meta, samples,
// events, channels, frames; archive_row_writer.hpp says what may be in them), written by raw
// SQL, and then every reader of runs is asked for every run: the run list, one run, its
// metadata, events, frames and samples (Archive), export to run-CSV and reading that back,
// the model lab's archive source (`rig model diagnose 3`: cli::load_runs), and the API that
// `rig runs`, the page and `rig export` use (/api/runs, /api/runs/N[/csv|/samples|/stream|
// /frames/K]), and the lab archive replicator's backlog of local runs.
// A finding is a memory error, UB, a leak, a hang (libFuzzer's -timeout), an exception that
// is not a runtime_error with a message (a refusal must say what is wrong), run data whose
// columns or channels differ in length, an API answer that does not arrive or is not what
// its content type says, or a run list that `rig runs` could not print.
#include <spdlog/spdlog.h>
#include <sqlite3.h>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <set>
#include <sstream>
#include <string>

#include "api_router.hpp"
#include "archive.hpp"
#include "archive_row_writer.hpp"
#include "fuzz_run_checks.hpp"
#include "fuzz_support.hpp"
#include "run_csv.hpp"
#include "run_loader.hpp"
#include "run_shipper.hpp"
#include "stream_hub.hpp"

namespace {

namespace http = boost::beast::http;
using rig::fuzz::check_columns;
using rig::fuzz::export_and_read_back;
using rig::fuzz::fail;
using rig::fuzz::refusal_allowed;

struct Fixture {
  Fixture() : hub(channels, 20.0, 50) {
    spdlog::set_level(spdlog::level::off);
    archive_path = (dir.path / "archive.sqlite").string();
    { rig::archive::Archive create(archive_path); }  // the product's schema, at its current version
    std::ifstream in(archive_path, std::ios::binary);
    empty_archive.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    std::ofstream(dir.path / "frames.bin", std::ios::binary)
        << std::string(16 + 64, '\x7f');  // header + 64 B of pixels
    frame_files = {(dir.path / "frames.bin").string(), (dir.path / "missing.bin").string(),
                   dir.path.string(), "/dev/zero"};
    hub.set_model(std::make_shared<const rig::model::ForceModel>(
        rig::model::ForceModel::load(RIG_FUZZ_MODEL_FILE)));
    config.archive.path = archive_path;
    context.channels = &channels;
    context.hub = &hub;
    context.config = &config;
    context.version = "fuzz";
    context.auth = rig::api::ApiAuth(std::string(rig::fuzz::kToken));
    context.guard = rig::api::RequestGuard("", "rigbench");
  }

  // A fresh archive file each input: the empty one, its WAL and shared memory gone.
  void reset_archive() const {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(archive_path + suffix);
    std::ofstream(archive_path, std::ios::binary) << empty_archive;
  }

  rig::fuzz::ScratchDir dir{"rig-fuzz-archive-rows"};
  std::string archive_path;
  std::string empty_archive;
  std::vector<std::string> frame_files;
  rig::rt::LoopChannels channels{1024};
  rig::service::StreamHub hub;
  rig::config::RigdConfig config;
  rig::api::ApiContext context;
};

Fixture& fixture() {
  static Fixture* f = new Fixture;  // never destroyed: an archive thread may outlive exit
  return *f;
}

void read_one_run(rig::archive::Archive& archive, std::int64_t id) {
  const std::string what = "run " + std::to_string(id);
  refusal_allowed(what + " row", [&] { (void)archive.find_run(id); });
  refusal_allowed(what + " metadata", [&] { (void)archive.run_meta(id); });
  refusal_allowed(what + " events", [&] { (void)archive.run_events(id); });
  refusal_allowed(what + " frames", [&] { (void)archive.run_frames(id); });
  refusal_allowed(what + " samples", [&] {
    const rig::model::RunData run = archive.load_run(id);
    check_columns(run, what);
    export_and_read_back(run, what);
  });
  if (id < 0) return;  // not a run id on the command line
  refusal_allowed(what + " for the model lab", [&] {
    for (const auto& run : rig::cli::load_runs({std::to_string(id)}, archive.path()))
      check_columns(run, what + " (lab)");
  });
}

// The archive as `rig export` and `rig model ...` open it: the listed runs and the writer's
// ids are read. Returns the listed runs.
std::set<std::int64_t> read_with_archive(const std::string& path) {
  std::set<std::int64_t> listed;
  refusal_allowed("open", [&] {
    rig::archive::Archive archive(path, true);
    for (const auto& row : archive.list_runs()) listed.insert(row.id);
    std::set<std::int64_t> ids(rig::fuzz::ArchiveRowWriter::kRunIds.begin(),
                               rig::fuzz::ArchiveRowWriter::kRunIds.end());
    ids.insert(listed.begin(), listed.end());
    for (const std::int64_t id : ids) read_one_run(archive, id);
  });
  // rigd's lab archive replicator reads the local runs (and their uuids) for its backlog.
  refusal_allowed("replication backlog",
                  [&] { (void)rig::lab_archive::RunShipper(path, "rig07", "fuzz").backlog(); });
  return listed;
}

// What `rig runs` reads of each run in /api/runs (control_commands.cpp list_runs).
void check_run_list(const nlohmann::json& list) {
  if (!list.contains("runs") || !list["runs"].is_array())
    fail("a run list without runs", list.dump().substr(0, 200));
  for (const auto& r : list["runs"]) {
    const auto text_or_absent = [&r](const char* key) {
      return !r.contains(key) || r[key].is_string();
    };
    const bool printable = r["run_id"].is_number_integer() && r["samples"].is_number_integer() &&
                           r["eye_id"].is_string() && r["outcome"].is_string() &&
                           text_or_absent("started_at") && text_or_absent("reason") &&
                           (!r.contains("iop_mmHg") || r["iop_mmHg"].is_number()) &&
                           (!r.contains("velocity_mm_s") || r["velocity_mm_s"].is_number());
    if (!printable) fail("a run `rig runs` cannot print", r.dump().substr(0, 200));
  }
}

rig::api::Response get(rig::api::ApiRouter& router, boost::asio::io_context& io,
                       const std::string& target) {
  rig::api::Request request{http::verb::get, target, 11};
  request.set(http::field::host, "rigbench:8080");
  request.set(http::field::authorization, std::string("Bearer ") + rig::fuzz::kToken);
  std::optional<rig::api::Response> response;
  router.handle(request, [&response](rig::api::Response&& r) { response = std::move(r); });
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!response && std::chrono::steady_clock::now() < give_up)
    io.run_one_for(std::chrono::seconds(1));
  if (!response) fail("no answer within 10 s", target);
  const std::string type((*response)[http::field::content_type]);
  if (type.rfind("application/json", 0) == 0 && !nlohmann::json::accept(response->body()))
    fail("an answer that is not JSON", target);
  return std::move(*response);
}

void read_through_api(const std::set<std::int64_t>& ids) {
  Fixture& f = fixture();
  boost::asio::io_context io;
  auto busy = boost::asio::make_work_guard(io);
  rig::api::ApiRouter router(io, f.context);
  const rig::api::Response list = get(router, io, "/api/runs");
  if (list.result() == http::status::ok) check_run_list(nlohmann::json::parse(list.body()));
  for (const std::int64_t id : ids) {
    if (id < 0 || id > 999'999'999'999'999'999) continue;  // not a run path (at most 18 digits)
    const std::string run = "/api/runs/" + std::to_string(id);
    for (const char* what : {"", "/csv", "/samples", "/stream", "/stream?from=2&limit=3"})
      get(router, io, run + what);
    for (int frame = 0; frame < 3; ++frame)
      get(router, io, run + "/frames/" + std::to_string(frame));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Fixture& f = fixture();
  f.reset_archive();
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(f.archive_path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK)
    fail("cannot open", f.archive_path);
  rig::fuzz::FuzzByteReader in(data, size);
  rig::fuzz::ArchiveRowWriter(db, in, f.frame_files).write_all();
  sqlite3_close(db);
  std::set<std::int64_t> ids = read_with_archive(f.archive_path);
  ids.insert(4);  // and one that is not there
  read_through_api(ids);
  return 0;
}
