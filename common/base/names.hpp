// Spellings of enumerators: one table per enum, {name, value} pairs, serves to_string,
// parsing with a one-line error that lists the spellings, and the "expected one of"
// lists of the case reader's messages.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "common/base/error.hpp"

namespace slide {

template <typename E>
struct Named {
  std::string_view name;
  E value;
};

/// The spelling of `value` in `names`, "unknown" for a value the table lacks.
template <typename E, std::size_t N>
constexpr std::string_view name_of(const std::array<Named<E>, N>& names, E value) {
  for (const auto& named : names) {
    if (named.value == value) return named.name;
  }
  return "unknown";
}

/// The spellings for a message: "a", "b" or "c" (quoted).
template <typename E, std::size_t N>
std::string quoted_names(const std::array<Named<E>, N>& names) {
  std::string text;
  for (std::size_t i = 0; i < N; ++i) {
    text += fmt::format("{}\"{}\"", i == 0 ? "" : i + 1 == N ? " or " : ", ", names[i].name);
  }
  return text;
}

/// The value spelled `text`; Error "where: unknown <what> "text" (expected …)" otherwise.
template <typename E, std::size_t N>
E parse_name(const std::array<Named<E>, N>& names, std::string_view text, std::string_view where,
             std::string_view what) {
  for (const auto& named : names) {
    if (named.name == text) return named.value;
  }
  throw Error("{}: unknown {} \"{}\" (expected {})", where, what, text, quoted_names(names));
}

}  // namespace slide
