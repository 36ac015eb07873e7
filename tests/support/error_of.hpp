#pragma once

// The message of the InvalidInput that `run` throws, or "" when it throws none.

#include <functional>
#include <string>

#include "mimpact/common/error.hpp"

namespace mimpact::testing {

inline std::string error_of(const std::function<void()>& run) {
  try {
    run();
  } catch (const InvalidInput& error) {
    return error.what();
  }
  return "";
}

}  // namespace mimpact::testing
