#include "common/geometry/triangle_rules.hpp"

#include <algorithm>
#include <array>

namespace slide {

bool has_triangle_rule(int count) {
  // The rules of their own (transfer/particle_layout.cpp), then the subdivisions.
  constexpr std::array<int, 6> named_rules{1, 3, 6, 7, 12, 13};
  if (std::find(named_rules.begin(), named_rules.end(), count) != named_rules.end()) return true;
  for (int n = 2; n <= max_triangle_subdivision; ++n) {
    if (n * n == count) return true;
  }
  return false;
}

std::string_view supported_triangle_counts() {
  return "1, 3, 6, 7, 12, 13, or a square n² ≥ 4 up to 1024 (4, 9, 16, 25, …)";
}

}  // namespace slide
