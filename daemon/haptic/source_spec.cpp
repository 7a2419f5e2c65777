#include "source_spec.hpp"

#include <stdexcept>

namespace rig::haptic {

SourceSpec SourceSpec::parse(const std::string& text) {
  const auto fail = [&text] {
    return std::invalid_argument("haptic source '" + text +
                                 "': expected model, model:FILE, run:ID or live");
  };
  if (text == "model") return {Kind::kModel, ""};
  if (text == "live") return {Kind::kLive, ""};
  const auto colon = text.find(':');
  if (colon == std::string::npos || colon + 1 == text.size()) throw fail();
  const std::string kind = text.substr(0, colon), argument = text.substr(colon + 1);
  if (kind == "model") return {Kind::kModel, argument};
  if (kind == "run") return {Kind::kRun, argument};
  throw fail();
}

}  // namespace rig::haptic
