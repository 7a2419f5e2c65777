#pragma once
// Turns the RT loop's stream ring into batched JSON messages (proto SampleBatch and
// StateEvent) every batch period, with the model prediction and the residual for every
// sample, and hands them to the sinks. Runs on its own thread: a slow sink never reaches
// the RT loop, which only sees a ring that may drop (counted) when nobody drains it.
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "force_model.hpp"
#include "loop_channels.hpp"
#include "stream_sink.hpp"

namespace rig::service {

class StreamHub {
 public:
  StreamHub(rt::LoopChannels& channels, double surface_mm, int batch_ms);
  ~StreamHub();

  void add_sink(StreamSink* sink);  // before start()
  void start();
  void stop();
  void set_model(std::shared_ptr<const model::ForceModel> model);
  std::shared_ptr<const model::ForceModel> model() const;
  // The model curve at an IOP as a JSON ModelInfo message.
  std::string model_curve_json(double iop_mmHg) const;
  double surface_mm() const { return surface_mm_; }
  // The model's force for one sample at depth x [mm] in its phase: the baseline while the
  // blade goes in, the force at the hold's depth [mm] (kept in hold_x_mm) in the hold, 0 on
  // the way out, NaN outside a cut. The archive replay (api/run_replay) uses it too.
  static double predict_at(const model::ForceModel& model, rt::CutPhase phase, double x_mm,
                           double iop_mmHg, double& hold_x_mm);

 private:
  struct Columns {
    std::vector<std::int64_t> cycle;
    std::vector<double> t_s, position_mm, x_mm, force_N, model_N, residual_N, iop_mmHg;
    std::vector<std::string> phase;
    void clear();
  };
  void run();
  void take_samples();
  void send_batch();
  void send_events();
  double predict(const rt::Sample& sample, const model::ForceModel& model, double iop);

  rt::LoopChannels* channels_;
  double surface_mm_;
  int batch_ms_;
  std::vector<StreamSink*> sinks_;
  mutable std::mutex model_mutex_;
  std::shared_ptr<const model::ForceModel> model_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  Columns columns_;
  std::int64_t run_id_ = 0;
  rt::RunState state_ = rt::RunState::kIdle;
  double hold_x_mm_ = 0.0;
};

}  // namespace rig::service
