#include "stream_hub.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <limits>

#include "model_lint.hpp"
#include "recorder.hpp"
#include "rig/proto/messages.hpp"

namespace rig::service {

void StreamHub::Columns::clear() {
  cycle.clear();
  t_s.clear();
  position_mm.clear();
  x_mm.clear();
  force_N.clear();
  model_N.clear();
  residual_N.clear();
  iop_mmHg.clear();
  phase.clear();
}

StreamHub::StreamHub(rt::LoopChannels& channels, double surface_mm, int batch_ms)
    : channels_(&channels), surface_mm_(surface_mm), batch_ms_(batch_ms) {}

StreamHub::~StreamHub() {
  stop();
}

void StreamHub::add_sink(StreamSink* sink) {
  sinks_.push_back(sink);
}

void StreamHub::start() {
  thread_ = std::thread([this] { run(); });
}

void StreamHub::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true);
  thread_.join();
}

void StreamHub::set_model(std::shared_ptr<const model::ForceModel> model) {
  std::lock_guard lock(model_mutex_);
  model_ = std::move(model);
}

std::shared_ptr<const model::ForceModel> StreamHub::model() const {
  std::lock_guard lock(model_mutex_);
  return model_;
}

std::string StreamHub::model_curve_json(double iop_mmHg) const {
  proto::ModelInfo info;
  const auto m = model();
  if (m) {
    info.file = m->path;
    info.name = m->name;
    for (const auto& e : m->effects) info.effects.push_back(e.name);
    for (double x = 0.0; x <= 14.0 + 1e-9; x += 0.02) {
      info.x_mm.push_back(x);
      info.force_N.push_back(m->baseline(x, iop_mmHg));
    }
  }
  info.iop_mmHg = iop_mmHg;
  nlohmann::json j = info;
  j["type"] = "model";
  // The page shows this beside the curve: a printed-form file is drawn as printed.
  if (m && m->form == model::ModelForm::kPrinted) j["warnings"] = {model::printed_form_warning(*m)};
  return j.dump();
}

double StreamHub::predict_at(const model::ForceModel& m, rt::CutPhase phase, double x, double iop,
                             double& hold_x_mm) {
  switch (phase) {
    case rt::CutPhase::kApproach:
    case rt::CutPhase::kInsert:
      hold_x_mm = x;
      return m.baseline(x, iop);
    case rt::CutPhase::kHold:
      return m.baseline(hold_x_mm, iop);
    case rt::CutPhase::kRetract:
      return 0.0;  // the blade leaves its own cut
    case rt::CutPhase::kNone:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double StreamHub::predict(const rt::Sample& s, const model::ForceModel& m, double iop) {
  return predict_at(m, s.phase, s.position_mm - surface_mm_, iop, hold_x_mm_);
}

void StreamHub::take_samples() {
  const auto m = model();
  const double iop = channels_->status.read().params.iop_mmHg;
  rt::Sample s;
  while (channels_->stream.try_pop(s)) {
    run_id_ = s.run_id;
    state_ = s.state;
    const double prediction = m ? predict(s, *m, iop) : std::numeric_limits<double>::quiet_NaN();
    columns_.cycle.push_back(static_cast<std::int64_t>(s.cycle));
    columns_.t_s.push_back(s.t_s);
    columns_.position_mm.push_back(s.position_mm);
    columns_.x_mm.push_back(s.position_mm - surface_mm_);
    columns_.force_N.push_back(s.force_N);
    columns_.model_N.push_back(prediction);
    columns_.residual_N.push_back(s.force_N - prediction);
    columns_.iop_mmHg.push_back(s.iop_mmHg);
    columns_.phase.emplace_back(rt::to_string(s.phase));
  }
}

void StreamHub::send_batch() {
  if (columns_.t_s.empty()) return;
  proto::SampleBatch batch;
  batch.type = "samples";
  batch.run_id = run_id_;
  batch.state = std::string(rt::to_string(state_));
  batch.cycle = columns_.cycle;
  batch.t_s = columns_.t_s;
  batch.position_mm = columns_.position_mm;
  batch.x_mm = columns_.x_mm;
  batch.force_N = columns_.force_N;
  batch.model_N = columns_.model_N;
  batch.residual_N = columns_.residual_N;
  batch.iop_mmHg = columns_.iop_mmHg;
  batch.phase = columns_.phase;
  batch.sent_unix_s =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  batch.loop_start_monotonic_s = static_cast<double>(channels_->counters.start_ns.load()) * 1e-9;
  auto message = std::make_shared<const std::string>(nlohmann::json(batch).dump());
  for (StreamSink* sink : sinks_) sink->publish(message);
  columns_.clear();
}

void StreamHub::send_events() {
  rt::Event e;
  while (channels_->stream_events.try_pop(e)) {
    proto::StateEvent event;
    event.type = "event";
    event.kind = std::string(rt::to_string(e.kind));
    event.t_s = e.t_s;
    event.state = std::string(rt::to_string(e.to));
    event.fault = std::string(rt::to_string(e.fault));
    event.run_id = e.run_id;
    event.message =
        e.kind == rt::EventKind::kFault ? describe_fault(e.fault, e.value)
        : e.kind == rt::EventKind::kCommand
            ? std::string(rt::to_string(e.command)) + ": " + std::string(rt::to_string(e.result))
            : std::string(rt::to_string(e.from)) + " -> " + std::string(rt::to_string(e.to));
    auto message = std::make_shared<const std::string>(nlohmann::json(event).dump());
    for (StreamSink* sink : sinks_) sink->publish(message);
    if (e.kind == rt::EventKind::kRunStarted) {
      auto curve = std::make_shared<const std::string>(
          model_curve_json(channels_->status.read().params.iop_mmHg));
      for (StreamSink* sink : sinks_) sink->publish(curve);
    }
  }
}

void StreamHub::run() {
  auto next = std::chrono::steady_clock::now();
  while (!stop_.load()) {
    next += std::chrono::milliseconds(batch_ms_);
    std::this_thread::sleep_until(next);
    take_samples();
    send_batch();
    send_events();
  }
}

}  // namespace rig::service
