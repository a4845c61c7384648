// Which numbers of material points a triangle can carry: the counts for which the
// transfer has a symmetric rule with positive weights and interior points
// (transfer/particle_layout.hpp builds the rules). The rule lives in common/ because the
// case reader refuses another count at its line of the case file, and common/ depends on
// no stage; fem2mpm's --particles-per-element asks the same function.
#pragma once

#include <string_view>

namespace slide {

/// Largest number of material points per direction of the Gauss–Legendre layout of a
/// quad (fem2mpm's NxM) or of an MPM cell (pure MPM): 32, the highest order the
/// quadrature tables reach at full precision.
inline constexpr int max_particles_per_direction = 32;

/// Largest n of the n×n subdivision rule (n² points).
inline constexpr int max_triangle_subdivision = 32;

/// True for 1, 3, 6, 7, 12, 13 and the squares n² with 2 ≤ n ≤ max_triangle_subdivision.
bool has_triangle_rule(int count);

/// Human-readable list of the supported counts, for messages and --help.
std::string_view supported_triangle_counts();

}  // namespace slide
