// Where the material points of one element sit, and what share of the element each one
// carries (docs/method.md §4).
//
// Quads: N_px × N_py points at the tensor-product Gauss–Legendre points of orders N_px
// and N_py of [−1, 1]²; the share of point (i, j) is w_i w_j / 4.
// Triangles: a fully symmetric rule with the requested number of points, all weights
// positive and all points strictly inside (a particle with negative mass, or outside
// its element, is not a particle). The rules, by count:
//   1        the centroid                                                    degree 1
//   3        Strang–Fix interior rule, barycentric orbit (2/3, 1/6, 1/6)     degree 2
//   6        Dunavant's 6-point rule                                         degree 4
//   7        Radon's 7-point rule (closed form with √15)                     degree 5
//   12       Dunavant's 12-point rule                                        degree 6
//   13       a positive 1+3+3+6 rule of this project (centroid weight 1/13)  degree 6
//   n² ≥ 4   centroids of the regular n×n subdivision into n² congruent
//            triangles, equal weights 1/n² (4, 9, 16, 25, …)                 degree 1
// The standard 4-point (degree 3) and 13-point (degree 7) rules have a negative centroid
// weight and are deliberately not used. transfer/README.md lists the rules in full.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "common/geometry/element.hpp"
#include "common/geometry/triangle_rules.hpp"

namespace slide::transfer {

/// Particles per element as the user asks for them: "N" (N × N per quad, N points per
/// triangle) or "NxM" (N × M per quad, N·M points per triangle).
struct ParticlesPerElement {
  int nx = 4;
  int ny = 4;
  int triangle = 16;
};
/// Parses "N" or "NxM" (N, M ≥ 1); throws Error naming `where` otherwise.
ParticlesPerElement parse_particles_per_element(std::string_view text, std::string_view where);

/// The reference points of one element's particles with their shares of the element.
struct ParticleLayout {
  ElementShape shape = ElementShape::quad4;
  /// Reference coordinates and shares; the shares are positive and sum to 1.
  std::vector<QuadraturePoint> points;
  /// Highest total polynomial degree the shares integrate exactly over the element.
  int degree = 1;
  /// "4x4" (quads) or "16" (triangles): goes into the particle file.
  std::string label;
  /// One line naming the rule, e.g. "4x4 Gauss–Legendre".
  std::string rule;

  int count() const { return static_cast<int>(points.size()); }
};

/// Largest Gauss–Legendre order accepted per direction.
inline constexpr int max_particle_order = max_particles_per_direction;

ParticleLayout quad_layout(int nx, int ny);
/// Throws Error listing the supported counts unless has_triangle_rule(count)
/// (common/geometry/triangle_rules.hpp, the one place that decides it).
ParticleLayout triangle_layout(int count);
/// The layout of one element shape for the user's request.
ParticleLayout make_layout(ElementShape shape, const ParticlesPerElement& request);

}  // namespace slide::transfer
