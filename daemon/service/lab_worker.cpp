#include "lab_worker.hpp"

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "archive.hpp"
#include "comparison.hpp"
#include "data_checks.hpp"
#include "diagnosis.hpp"
#include "lab_json.hpp"
#include "model_fit.hpp"
#include "report/lab_views.hpp"

namespace rig::service {
namespace {

constexpr std::size_t kMaxQueuedJobs = 8;

std::string error_json(const std::string& what) {
  return nlohmann::json{{"error", what}}.dump();
}

}  // namespace

LabWorker::LabWorker(std::string archive_path, const StreamHub& hub)
    : archive_path_(std::move(archive_path)), hub_(&hub), thread_([this] { run(); }) {}

LabWorker::~LabWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void LabWorker::submit(const std::string& action, const proto::LabRequest& request, Done done) {
  {
    std::lock_guard lock(mutex_);
    if (jobs_.size() < kMaxQueuedJobs) {
      jobs_.push_back({action, request, std::move(done)});
      wake_.notify_one();
      return;
    }
  }
  done(503,
       error_json("the model lab is busy: " + std::to_string(kMaxQueuedJobs) + " requests queued"));
}

void LabWorker::run() {
  while (true) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
      if (stop_) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    execute(job);
  }
}

void LabWorker::execute(const Job& job) {
  try {
    if (job.request.runs.empty())
      return job.done(400, error_json("field 'runs': pick at least one run"));
    archive::Archive archive(archive_path_, true);
    std::vector<model::RunData> runs;
    for (const std::int64_t id : job.request.runs) runs.push_back(archive.load_run(id));
    model::ForceModel model =
        job.request.model
            ? model::ForceModel::load(*job.request.model)
            : (hub_->model() ? *hub_->model() : model::ForceModel::paper_interpreted());
    const std::vector<std::string> effects =
        job.request.effects.value_or(std::vector<std::string>{});
    nlohmann::json out;
    // "series": the same plots as the CLI's --report (residual against depth by direction,
    // in the hold, per-run small multiples; before/after for fit).
    if (job.action == "compare") {
      const model::LabViews views = model::compare_views(model, runs, false);
      out = model::to_json(views.before);
      out["series"] = model::views_series(runs, views);
    } else if (job.action == "diagnose") {
      model::require_fittable(model, "diagnose");
      model::DiagnoseOptions options;
      options.with = effects;
      model::Diagnosis diagnosis = model::diagnose(model, runs, options);
      const model::LabViews views = model::diagnose_views(model, runs);
      for (auto& w : model::base_misfit_warnings(model, views.before))
        diagnosis.warnings.push_back(std::move(w));
      out = model::to_json(diagnosis);
      out["series"] = model::views_series(runs, views);
    } else {
      model::require_fittable(model, "fit");
      model::FitReport fit = model::fit_model(model, runs, effects);
      const model::LabViews views = model::fit_views(model, fit.fitted, runs);
      for (auto& w : model::base_misfit_warnings(model, views.before))
        fit.warnings.push_back(std::move(w));
      out = model::to_json(fit);
      out["series"] = model::views_series(runs, views);
    }
    job.done(200, out.dump());
  } catch (const std::invalid_argument& e) {
    job.done(400, error_json(e.what()));
  } catch (const std::exception& e) {
    spdlog::warn("model lab {}: {}", job.action, e.what());
    job.done(422, error_json(e.what()));
  }
}

}  // namespace rig::service
