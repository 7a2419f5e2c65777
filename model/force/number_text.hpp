#pragma once
// printf-style text with up to three numbers, for findings and warnings that quote sizes.
#include <cstdio>
#include <string>

namespace rig::model {

inline std::string number_text(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

}  // namespace rig::model
