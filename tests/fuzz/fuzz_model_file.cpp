// libFuzzer target: a model file (TOML: the IOP table, continuous or printed parameters,
// effects, and [terms.NAME] user terms whose expressions muParser compiles), as `rig model
// lint`, the lab and rigd's POST /api/model read it: load it, lint it, evaluate the baseline,
// and compile and evaluate every user term. A file is either refused with a ModelFileError
// naming the file and key or loads; any other exception, a memory error or UB is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "effects/user_expression.hpp"
#include "force_model.hpp"
#include "model_lint.hpp"

namespace {

void exercise(const rig::model::ForceModel& model) {
  (void)rig::model::lint_model(model);
  for (const double iop : {5.0, 15.0, 40.0}) {
    for (const double x : {0.0, 1.0, 7.0, 14.0}) (void)model.baseline(x, iop);
  }
  for (const auto* terms : {&model.user_terms, &model.candidate_terms}) {
    for (const rig::model::UserTerm& term : *terms) {
      try {
        const rig::model::effects::UserExpression expression(term);
        (void)expression.shared_params();
        (void)expression.meaning();
      } catch (const rig::model::ModelFileError&) {
        // refused, naming the term
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/rig-fuzz-model-" + std::to_string(::getpid()) + ".toml";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    exercise(rig::model::ForceModel::load(path));
  } catch (const rig::model::ModelFileError&) {
    // refused with file and key: fine
  }
  try {
    for (const rig::model::UserTerm& term : rig::model::load_user_terms(path)) {
      try {
        const rig::model::effects::UserExpression expression(term);
      } catch (const rig::model::ModelFileError&) {
      }
    }
  } catch (const rig::model::ModelFileError&) {
  }
  return 0;
}
