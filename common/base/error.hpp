// One exception type for every user-facing failure. Its message is a single line that
// names the file, key, dataset or item at fault and what was expected; each program's
// main prints it on stderr and exits non-zero. Build one with a format string:
// `throw Error("{}: dataset {} missing", path, name)`.
#pragma once

#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace slide {

class Error : public std::runtime_error {
 public:
  template <typename... Args>
  Error(fmt::format_string<Args...> format, Args&&... args)
      : std::runtime_error(fmt::format(format, std::forward<Args>(args)...)) {}
};

}  // namespace slide
