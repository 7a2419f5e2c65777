#pragma once
#include <stdexcept>
#include <string>

namespace rig::config {

// A configuration problem, with where it is: "FILE:LINE: key 'a.b': what is wrong".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rig::config
