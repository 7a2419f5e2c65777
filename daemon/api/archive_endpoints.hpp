#pragma once
// The API's archive work — run lists, run details, CSV exports, creating and discarding run
// rows — on a thread of its own. The I/O thread answers stop and e-stop; it must never wait
// behind a whole-run export or a write that waits on SQLite's lock. Results go back to the
// I/O thread, which alone writes to connections.
#include <boost/asio/io_context.hpp>
#include <boost/asio/thread_pool.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "api_context.hpp"
#include "archive.hpp"
#include "http_types.hpp"

namespace rig::api {

class ArchiveEndpoints {
 public:
  // Nice value of the archive thread (0 = the I/O thread's, 19 = the lowest priority): it
  // yields the CPU to the I/O thread that answers stop and e-stop.
  static constexpr int kArchiveThreadNice = 10;
  ArchiveEndpoints(boost::asio::io_context& io, ApiContext& context);
  ~ArchiveEndpoints();

  void get_runs(const Request& request, Responder respond);
  // what: "" (details, metadata, events), "/csv" (the whole run), "/samples" (decimated),
  // "/stream" (every sample from ?from=CYCLE with model, events, frames: run_replay.hpp),
  // "/frames/N" (frame N's grey pixels).
  void get_run(const Request& request, std::int64_t run_id, const std::string& what,
               Responder respond);
  // Creates the run's row, then calls then(run_id) on the I/O thread (errors are answered).
  void create_run(const Request& request, archive::NewRun row,
                  std::function<void(std::int64_t)> then, Responder respond);
  // The loop refused the run: the row never held a sample, so it goes (no 'cancelled' rows).
  void discard_refused_run(std::int64_t run_id, const std::string& why);

 private:
  void get_replay(const Request& request, std::int64_t run_id, const std::string& what,
                  Responder respond);
  // Runs work on the archive thread; its response (or the error) is sent from the I/O thread.
  void on_archive(const Request& request, Responder respond,
                  std::function<Response(archive::Archive&)> work);
  archive::Archive& archive();

  boost::asio::io_context* io_;
  ApiContext* context_;
  boost::asio::thread_pool pool_{1};
  std::unique_ptr<archive::Archive> archive_;  // used on pool_'s thread only
};

}  // namespace rig::api
