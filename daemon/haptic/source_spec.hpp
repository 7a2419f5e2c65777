#pragma once
// Which force a haptic session renders, as written on the command line or in the API:
// "model" (the installed paper-interpreted model), "model:FILE" (a model file, e.g. one
// the model lab saved), "run:ID" (an archived run id or a run-CSV file) or "live".
#include <string>

namespace rig::haptic {

struct SourceSpec {
  enum class Kind { kModel, kRun, kLive };
  Kind kind = Kind::kModel;
  std::string argument;  // file or run id; empty for the default model and live

  // Throws std::invalid_argument naming the text and what is accepted.
  static SourceSpec parse(const std::string& text);
};

}  // namespace rig::haptic
