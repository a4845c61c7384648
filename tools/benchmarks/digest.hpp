// A hash of the bits of a state's arrays, printed by the benchmarks: equal digests mean
// bit-identical results, e.g. before and after a kernel change, or on 1 and 2 threads.
#pragma once

#include <cstddef>
#include <cstdint>

namespace slide::bench {

/// FNV-1a over the bytes of each array (contiguous containers of plain values), in order.
template <class... Arrays>
std::uint64_t digest(const Arrays&... arrays) {
  std::uint64_t hash = 14695981039346656037ull;
  auto add = [&hash](const auto& values) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    for (std::size_t i = 0; i < values.size() * sizeof(values[0]); ++i) {
      hash = (hash ^ bytes[i]) * 1099511628211ull;
    }
  };
  (add(arrays), ...);
  return hash;
}

}  // namespace slide::bench
