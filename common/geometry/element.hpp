// The one element interface: reference shapes, shape functions and their derivatives,
// quadrature rules and isoparametric geometry. The FE solver integrates with it and the
// transfer places material points with it, so both agree on what an element is.
//
// Reference elements (nodes counter-clockwise):
//   quad4: [−1,1]², nodes (−1,−1) (1,−1) (1,1) (−1,1), N_k = ¼(1+ξ_k ξ)(1+η_k η)
//   tri3 : nodes (0,0) (1,0) (0,1), N = (1−ξ−η, ξ, η)
#pragma once

#include <array>
#include <span>
#include <string_view>
#include <vector>

#include "common/base/types.hpp"

namespace slide {

/// Geometry of an element.
enum class ElementShape { quad4, tri3 };
/// Geometry plus the solver's integration rule.
enum class ElementType { quad4_1gp, quad4_2x2, tri3 };

/// "quad4-1gp", "quad4-2x2", "tri3" (case files and checkpoints use these names).
std::string_view to_string(ElementType type);
ElementType parse_element_type(std::string_view text, std::string_view where);
/// "quad4" or "tri3" (the `type` attribute of /elements/connectivity).
std::string_view to_string(ElementShape shape);
ElementShape parse_element_shape(std::string_view text, std::string_view where);

ElementShape shape_of(ElementType type);
int nodes_per_element(ElementShape shape);
inline int nodes_per_element(ElementType type) {
  return nodes_per_element(shape_of(type));
}

inline constexpr int max_nodes_per_element = 4;

/// A point of the reference element with its weight (weights sum to the reference
/// measure: 4 for quad4, ½ for tri3).
struct QuadraturePoint {
  Vec2 xi;
  double weight;
};

/// The rule the FE solver integrates with: 1 point, 2×2 points, or the centroid.
std::span<const QuadraturePoint> quadrature_rule(ElementType type);

/// Gauss–Legendre rule of `order` points on [−1, 1] (weights sum to 2), any order ≥ 1.
struct GaussLegendre {
  std::vector<double> points;
  std::vector<double> weights;
};
GaussLegendre gauss_legendre(int order);
/// Tensor-product Gauss–Legendre rule of nx × ny points on the reference square,
/// ordered with ξ fastest.
std::vector<QuadraturePoint> tensor_gauss_legendre(int nx, int ny);

Vec2 reference_centre(ElementShape shape);
/// Area of the reference element: 4 (quad4) or ½ (tri3).
double reference_measure(ElementShape shape);

/// Shape function values; entries past nodes_per_element are zero.
using ShapeValues = std::array<double, max_nodes_per_element>;
/// Row k: (∂N_k/∂ξ, ∂N_k/∂η), or (∂N_k/∂x, ∂N_k/∂y) once mapped; unused rows are zero.
using ShapeGradients = Eigen::Matrix<double, max_nodes_per_element, 2>;
/// Row k: coordinates of node k; unused rows are ignored.
using ElementNodes = Eigen::Matrix<double, max_nodes_per_element, 2>;

ShapeValues shape_functions(ElementShape shape, const Vec2& xi);
ShapeGradients shape_derivatives(ElementShape shape, const Vec2& xi);

/// x(ξ) = Σ_k N_k(ξ) x_k.
Vec2 map_to_physical(ElementShape shape, const ElementNodes& nodes, const Vec2& xi);
/// J_ij = ∂x_i/∂ξ_j at ξ.
Mat2 jacobian(ElementShape shape, const ElementNodes& nodes, const Vec2& xi);
/// Physical gradients ∂N_k/∂x at ξ; throws nothing, the caller checks det J.
ShapeGradients physical_gradients(ElementShape shape, const ElementNodes& nodes, const Vec2& xi,
                                  double* det_jacobian = nullptr);
/// Signed area (positive for counter-clockwise nodes): the shoelace formula, exact for
/// straight-sided elements.
double element_area(ElementShape shape, const ElementNodes& nodes);

/// Row-sum lumped mass of an element of density ρ: m_k = ρ ∫ N_k dA per node k (ρA/3
/// for triangles; quads by the 2×2 rule, exact for N_k det J on straight sides). The one
/// lumped mass of the project: fem-solve's nodal masses and fem2mpm's report of the FE
/// momentum and kinetic energy.
ShapeValues lumped_element_mass(ElementShape shape, const ElementNodes& nodes, double density);

/// The reference coordinates (ξ, η) of the element's corner nodes, in node order.
std::span<const Vec2> reference_corners(ElementShape shape);
/// The square of the element's longest edge: the scale its det J is measured against.
double longest_edge_squared(ElementShape shape, const ElementNodes& nodes);
/// The mesh checks' zero: an element whose det J (or signed area) is at most this fraction
/// of its longest edge squared is inverted or degenerate. Exact zeros come out as zeros;
/// round-off does not hide a collapsed element.
inline constexpr double degenerate_jacobian_fraction = 1e-14;

/// The shape of one corner k of an element: e1 and e2 are the edges from node k to the
/// next and to the previous node (counter-clockwise), det[e1 e2] their cross product.
/// det J of the isoparametric map at the corner is det[e1 e2]/4 (quad4: ∂x/∂ξ and ∂x/∂η
/// are half the edges there) or det[e1 e2] (tri3: det J is the same everywhere).
struct CornerJacobian {
  int corner = 0;
  double det_jacobian = 0.0;  ///< det J at the corner
  /// det[e1 e2]/(|e1||e2|), the sine of the corner angle, divided by sin 60° for a
  /// triangle: 1 for the square and for the equilateral triangle, cos θ at every corner of
  /// a rhombus sheared by θ, 0 for a flat or collapsed corner, < 0 for a folded one. A
  /// cross product within the mesh checks' zero (degenerate_jacobian_fraction × the
  /// longest edge squared) counts as 0, so a corner with a zero-length edge gives 0.
  double scaled_jacobian = 0.0;
};

/// Corner `corner` (node index, 0 ≤ corner < nodes_per_element) of the element.
CornerJacobian corner_jacobian(ElementShape shape, const ElementNodes& nodes, int corner);
/// The corner with the smallest scaled Jacobian (the first of equal ones).
CornerJacobian worst_corner(ElementShape shape, const ElementNodes& nodes);
/// The element's scaled Jacobian: the minimum over its corners (see CornerJacobian). It
/// measures shape only: a stretched rectangle gives 1, a sheared element less, at any
/// size, so it sees the distortion of isochoric shear that |J_t|/|J_0| does not.
inline double scaled_jacobian(ElementShape shape, const ElementNodes& nodes) {
  return worst_corner(shape, nodes).scaled_jacobian;
}

/// The one definition of an inverted element, shared by fem-solve (mesh quality) and
/// fem2mpm (the transfer refuses inverted elements): det J < 0 somewhere in the closed
/// element, which is det J < 0 at one of its corners, or an element collapsed to zero
/// area. For tri3 det J is constant; for quad4 it is affine in (ξ, η) (the ξη terms of
/// ∂x/∂ξ × ∂x/∂η cancel), so its minimum over the reference square is at a corner, and the
/// test covers the centre, every Gauss point, every particle point and V_t^e ≤ 0 (V_t^e
/// is the sum of the four corner values of det J). "< 0" and "zero area" are up to the
/// mesh checks' zero. A single flat corner (scaled Jacobian 0, e.g. a free face folded
/// exactly onto the base, where the contact plane puts its nodes) with a positive area
/// is degenerate, not inverted: det J > 0 inside it, every Gauss and particle point is
/// fine, and the history's scaled_jacobian_min = 0 tells the user.
inline bool is_inverted(ElementShape shape, const ElementNodes& nodes) {
  if (!(scaled_jacobian(shape, nodes) >= 0.0)) return true;  // a folded corner, or NaN
  return !(element_area(shape, nodes) >
           degenerate_jacobian_fraction * longest_edge_squared(shape, nodes));
}

}  // namespace slide
