#include "common/geometry/element.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "common/base/error.hpp"
#include "common/base/names.hpp"

namespace slide {

namespace {

constexpr std::array<Named<ElementType>, 3> element_type_names{{
    {"quad4-1gp", ElementType::quad4_1gp},
    {"quad4-2x2", ElementType::quad4_2x2},
    {"tri3", ElementType::tri3},
}};
constexpr std::array<Named<ElementShape>, 2> element_shape_names{{
    {"quad4", ElementShape::quad4},
    {"tri3", ElementShape::tri3},
}};

}  // namespace

std::string_view to_string(ElementType type) {
  return name_of(element_type_names, type);
}

ElementType parse_element_type(std::string_view text, std::string_view where) {
  return parse_name(element_type_names, text, where, "element type");
}

std::string_view to_string(ElementShape shape) {
  return name_of(element_shape_names, shape);
}

ElementShape parse_element_shape(std::string_view text, std::string_view where) {
  return parse_name(element_shape_names, text, where, "element shape");
}

ElementShape shape_of(ElementType type) {
  return type == ElementType::tri3 ? ElementShape::tri3 : ElementShape::quad4;
}

int nodes_per_element(ElementShape shape) {
  return shape == ElementShape::quad4 ? 4 : 3;
}

std::span<const QuadraturePoint> quadrature_rule(ElementType type) {
  static const double g = 1.0 / std::sqrt(3.0);
  static const std::array<QuadraturePoint, 1> one_point{{{Vec2(0.0, 0.0), 4.0}}};
  static const std::array<QuadraturePoint, 4> two_by_two{
      {{Vec2(-g, -g), 1.0}, {Vec2(g, -g), 1.0}, {Vec2(g, g), 1.0}, {Vec2(-g, g), 1.0}}};
  static const std::array<QuadraturePoint, 1> centroid{{{Vec2(1.0 / 3.0, 1.0 / 3.0), 0.5}}};
  switch (type) {
    case ElementType::quad4_1gp:
      return one_point;
    case ElementType::quad4_2x2:
      return two_by_two;
    case ElementType::tri3:
      return centroid;
  }
  return {};
}

namespace {

/// Legendre polynomial P_n(x) and its derivative, by the three-term recurrence.
std::pair<double, double> legendre(int n, double x) {
  double p_previous = 1.0, p = x;
  for (int k = 2; k <= n; ++k) {
    const double p_next = ((2.0 * k - 1.0) * x * p - (k - 1.0) * p_previous) / k;
    p_previous = p;
    p = p_next;
  }
  if (n == 0) return {1.0, 0.0};
  return {p, n * (x * p - p_previous) / (x * x - 1.0)};
}

}  // namespace

GaussLegendre gauss_legendre(int order) {
  if (order < 1) throw Error("Gauss–Legendre order {} is not admissible (expected ≥ 1)", order);
  const auto n = static_cast<std::size_t>(order);
  GaussLegendre rule{std::vector<double>(n), std::vector<double>(n)};
  // Newton iteration on the roots of P_n from the classic cosine first guess. The rule
  // is symmetric: compute one half and mirror it (exact zero for odd orders).
  for (std::size_t i = 0; i < (n + 1) / 2; ++i) {
    double x = std::cos(std::numbers::pi * (static_cast<double>(i) + 0.75) / (order + 0.5));
    if (2 * i + 1 == n) {
      x = 0.0;
    } else {
      for (int iteration = 0; iteration < 100; ++iteration) {
        const auto [p, dp] = legendre(order, x);
        const double dx = p / dp;
        x -= dx;
        if (std::abs(dx) < 1e-16) break;
      }
    }
    const double dp = order == 1 ? 1.0 : legendre(order, x).second;
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    rule.points[i] = -x;
    rule.points[n - 1 - i] = x;
    rule.weights[i] = w;
    rule.weights[n - 1 - i] = w;
  }
  return rule;
}

std::vector<QuadraturePoint> tensor_gauss_legendre(int nx, int ny) {
  const GaussLegendre gx = gauss_legendre(nx);
  const GaussLegendre gy = gauss_legendre(ny);
  std::vector<QuadraturePoint> rule;
  rule.reserve(static_cast<std::size_t>(nx * ny));
  for (std::size_t j = 0; j < gy.points.size(); ++j) {
    for (std::size_t i = 0; i < gx.points.size(); ++i) {
      rule.push_back({Vec2(gx.points[i], gy.points[j]), gx.weights[i] * gy.weights[j]});
    }
  }
  return rule;
}

Vec2 reference_centre(ElementShape shape) {
  return shape == ElementShape::quad4 ? Vec2(0.0, 0.0) : Vec2(1.0 / 3.0, 1.0 / 3.0);
}

double reference_measure(ElementShape shape) {
  return shape == ElementShape::quad4 ? 4.0 : 0.5;
}

ShapeValues shape_functions(ElementShape shape, const Vec2& xi) {
  if (shape == ElementShape::quad4) {
    const double xm = 1.0 - xi.x(), xp = 1.0 + xi.x();
    const double ym = 1.0 - xi.y(), yp = 1.0 + xi.y();
    return {0.25 * xm * ym, 0.25 * xp * ym, 0.25 * xp * yp, 0.25 * xm * yp};
  }
  return {1.0 - xi.x() - xi.y(), xi.x(), xi.y(), 0.0};
}

ShapeGradients shape_derivatives(ElementShape shape, const Vec2& xi) {
  ShapeGradients d = ShapeGradients::Zero();
  if (shape == ElementShape::quad4) {
    const double xm = 1.0 - xi.x(), xp = 1.0 + xi.x();
    const double ym = 1.0 - xi.y(), yp = 1.0 + xi.y();
    d << -0.25 * ym, -0.25 * xm,  //
        0.25 * ym, -0.25 * xp,    //
        0.25 * yp, 0.25 * xp,     //
        -0.25 * yp, 0.25 * xm;
    return d;
  }
  d << -1.0, -1.0,  //
      1.0, 0.0,     //
      0.0, 1.0,     //
      0.0, 0.0;
  return d;
}

Vec2 map_to_physical(ElementShape shape, const ElementNodes& nodes, const Vec2& xi) {
  const ShapeValues n = shape_functions(shape, xi);
  Vec2 x = Vec2::Zero();
  for (int k = 0; k < nodes_per_element(shape); ++k) {
    x += n[static_cast<std::size_t>(k)] * nodes.row(k).transpose();
  }
  return x;
}

Mat2 jacobian(ElementShape shape, const ElementNodes& nodes, const Vec2& xi) {
  // J = Σ_k x_k ⊗ ∂N_k/∂ξ; unused rows of the derivative matrix are zero.
  return nodes.transpose() * shape_derivatives(shape, xi);
}

ShapeGradients physical_gradients(ElementShape shape, const ElementNodes& nodes, const Vec2& xi,
                                  double* det_jacobian) {
  const ShapeGradients d = shape_derivatives(shape, xi);
  const Mat2 j = nodes.transpose() * d;
  const double det = j.determinant();
  if (det_jacobian != nullptr) *det_jacobian = det;
  // ∂N/∂x = ∂N/∂ξ · J⁻¹
  const Mat2 j_inverse = Mat2{{j(1, 1), -j(0, 1)}, {-j(1, 0), j(0, 0)}} / det;
  return d * j_inverse;
}

std::span<const Vec2> reference_corners(ElementShape shape) {
  static const std::array<Vec2, 4> quad4{Vec2(-1.0, -1.0), Vec2(1.0, -1.0), Vec2(1.0, 1.0),
                                         Vec2(-1.0, 1.0)};
  static const std::array<Vec2, 3> tri3{Vec2(0.0, 0.0), Vec2(1.0, 0.0), Vec2(0.0, 1.0)};
  if (shape == ElementShape::quad4) return quad4;
  return tri3;
}

double longest_edge_squared(ElementShape shape, const ElementNodes& nodes) {
  const int n = nodes_per_element(shape);
  double longest2 = 0.0;
  for (int k = 0; k < n; ++k) {
    longest2 = std::max(longest2, (nodes.row((k + 1) % n) - nodes.row(k)).squaredNorm());
  }
  return longest2;
}

CornerJacobian corner_jacobian(ElementShape shape, const ElementNodes& nodes, int corner) {
  const int n = nodes_per_element(shape);
  // det J at a corner is det[e1 e2] scaled by the reference element (see element.hpp);
  // a triangle's corners are normalised by the equilateral's sin 60° = √3/2.
  const double det_per_cross = shape == ElementShape::quad4 ? 0.25 : 1.0;
  const double normalisation = shape == ElementShape::quad4 ? 1.0 : 2.0 / std::sqrt(3.0);
  const double zero = degenerate_jacobian_fraction * longest_edge_squared(shape, nodes);
  const Vec2 x = nodes.row(corner).transpose();
  const Vec2 e1 = nodes.row((corner + 1) % n).transpose() - x;
  const Vec2 e2 = nodes.row((corner + n - 1) % n).transpose() - x;
  const double cross = e1.x() * e2.y() - e1.y() * e2.x();
  const double scaled =
      std::abs(cross) <= zero ? 0.0 : normalisation * cross / (e1.norm() * e2.norm());
  return {corner, det_per_cross * cross, scaled};
}

CornerJacobian worst_corner(ElementShape shape, const ElementNodes& nodes) {
  CornerJacobian worst = corner_jacobian(shape, nodes, 0);
  for (int k = 1; k < nodes_per_element(shape); ++k) {
    const CornerJacobian c = corner_jacobian(shape, nodes, k);
    // A NaN corner (non-finite nodes) is kept as the worst: such an element is inverted.
    if (c.scaled_jacobian < worst.scaled_jacobian || std::isnan(c.scaled_jacobian)) worst = c;
  }
  return worst;
}

double element_area(ElementShape shape, const ElementNodes& nodes) {
  const int n = nodes_per_element(shape);
  double twice_area = 0.0;
  for (int k = 0; k < n; ++k) {
    const int next = (k + 1) % n;
    twice_area += nodes(k, 0) * nodes(next, 1) - nodes(next, 0) * nodes(k, 1);
  }
  return 0.5 * twice_area;
}

ShapeValues lumped_element_mass(ElementShape shape, const ElementNodes& nodes, double density) {
  ShapeValues mass{};
  if (shape == ElementShape::tri3) {
    mass.fill(0.0);
    const double share = density * element_area(shape, nodes) / 3.0;
    for (int k = 0; k < 3; ++k) mass[static_cast<std::size_t>(k)] = share;
    return mass;
  }
  for (const auto& point : quadrature_rule(ElementType::quad4_2x2)) {
    const ShapeValues n = shape_functions(shape, point.xi);
    const double w = point.weight * jacobian(shape, nodes, point.xi).determinant();
    for (std::size_t k = 0; k < 4; ++k) mass[k] += density * n[k] * w;
  }
  return mass;
}

}  // namespace slide
