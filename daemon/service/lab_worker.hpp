#pragma once
// The model lab behind the API: compare / diagnose / fit on archived runs, one job at a time
// on its own thread with its own read-only archive connection. A bounded queue: when it is
// full the request is refused (503), never blocking the API's I/O thread.
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "lab_service.hpp"
#include "stream_hub.hpp"

namespace rig::service {

class LabWorker final : public api::LabService {
 public:
  LabWorker(std::string archive_path, const StreamHub& hub);
  ~LabWorker() override;
  void submit(const std::string& action, const proto::LabRequest& request, Done done) override;

 private:
  struct Job {
    std::string action;
    proto::LabRequest request;
    Done done;
  };
  void run();
  void execute(const Job& job);

  std::string archive_path_;
  const StreamHub* hub_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> jobs_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace rig::service
