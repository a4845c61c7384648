// The message a refused input gives, for tests that check what an error says.
#pragma once

#include <string>

#include "common/base/error.hpp"

namespace slide::testing {

/// The message of the Error that `function` throws, or "no error" when it returns.
std::string error_of(const auto& function) {
  try {
    function();
  } catch (const Error& error) {
    return error.what();
  }
  return "no error";
}

}  // namespace slide::testing
