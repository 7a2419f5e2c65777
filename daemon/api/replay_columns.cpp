#include "replay_columns.hpp"

#include <nlohmann/json.hpp>

#include <limits>
#include <utility>

#include "stream_hub.hpp"

namespace rig::api {

ReplayColumns::ReplayColumns(std::shared_ptr<const model::ForceModel> model, double surface_mm,
                             double iop_mmHg)
    : model_(std::move(model)), surface_mm_(surface_mm), iop_mmHg_(iop_mmHg) {}

void ReplayColumns::add(std::int64_t cycle, double t_s, double position_mm, double force_N,
                        double iop_mmHg, rt::CutPhase phase) {
  const double x_mm = position_mm - surface_mm_;
  const double m = model_
                       ? service::StreamHub::predict_at(*model_, phase, x_mm, iop_mmHg_, hold_x_mm_)
                       : std::numeric_limits<double>::quiet_NaN();
  cycle_.push_back(cycle);
  t_.push_back(t_s);
  x_.push_back(x_mm);
  force_.push_back(force_N);
  predicted_.push_back(m);
  residual_.push_back(force_N - m);
  iop_.push_back(iop_mmHg);
  phase_.emplace_back(rt::to_string(phase));
}

void ReplayColumns::write(nlohmann::json& j, std::int64_t from_cycle, bool more) const {
  j["next_cycle"] = cycle_.empty() ? from_cycle : cycle_.back() + 1;
  j["more"] = more;
  j["cycle"] = cycle_;
  j["t_s"] = t_;
  j["x_mm"] = x_;
  j["force_N"] = force_;
  j["model_N"] = predicted_;
  j["residual_N"] = residual_;
  j["iop_mmHg"] = iop_;
  j["phase"] = phase_;
  j["surface_mm"] = surface_mm_;
  j["model_iop_mmHg"] = iop_mmHg_;
}

}  // namespace rig::api
