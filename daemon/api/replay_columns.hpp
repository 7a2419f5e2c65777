#pragma once
// One replayed run's samples column-wise, as the live SampleBatch carries them (cycle, loop
// time, depth, force, the model's force and the residual, IOP, phase), for the page's
// whole-run view. Shared by the local archive's replay (run_replay) and the lab archive's
// (lab_run_replay): the rows come from SQLite or PostgreSQL, the columns are the same.
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "force_model.hpp"
#include "run_types.hpp"

namespace rig::api {

class ReplayColumns {
 public:
  // model may be null (model and residual are then NaN); surface [mm]: carriage position of
  // the corneal surface; iop [mmHg]: the run's IOP, at which the model is drawn.
  ReplayColumns(std::shared_ptr<const model::ForceModel> model, double surface_mm, double iop_mmHg);
  // One sample; iop_mmHg may be NaN (not recorded).
  void add(std::int64_t cycle, double t_s, double position_mm, double force_N, double iop_mmHg,
           rt::CutPhase phase);
  std::size_t size() const { return cycle_.size(); }
  // Writes the columns, next_cycle, more, surface_mm and model_iop_mmHg into j.
  void write(nlohmann::json& j, std::int64_t from_cycle, bool more) const;

 private:
  std::shared_ptr<const model::ForceModel> model_;
  double surface_mm_, iop_mmHg_;
  double hold_x_mm_ = 0.0;  // the hold's depth, carried from sample to sample (predict_at)
  std::vector<std::int64_t> cycle_;
  std::vector<double> t_, x_, force_, predicted_, residual_, iop_;
  std::vector<std::string> phase_;
};

}  // namespace rig::api
