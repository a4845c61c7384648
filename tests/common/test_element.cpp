// The element interface: properties every isoparametric element must have exactly.
#include <cmath>

#include <gtest/gtest.h>

#include "common/geometry/element.hpp"

namespace slide {
namespace {

const std::array<ElementShape, 2> shapes{ElementShape::quad4, ElementShape::tri3};

// A distorted but valid element of each shape.
ElementNodes distorted_nodes(ElementShape shape) {
  ElementNodes x = ElementNodes::Zero();
  if (shape == ElementShape::quad4) {
    x << 0.1, -0.2, 2.3, 0.1, 1.9, 1.7, -0.3, 1.2;
  } else {
    x << 0.2, 0.1, 1.7, -0.3, 0.4, 1.5, 0.0, 0.0;
  }
  return x;
}

std::vector<Vec2> sample_points(ElementShape shape) {
  if (shape == ElementShape::quad4) return {{0.0, 0.0}, {0.3, -0.7}, {-0.9, 0.4}, {1.0, 1.0}};
  return {{1.0 / 3.0, 1.0 / 3.0}, {0.1, 0.7}, {0.6, 0.2}, {0.0, 0.0}};
}

TEST(Element, ShapeFunctionsArePartitionOfUnityAndInterpolateNodes) {
  for (auto shape : shapes) {
    for (const auto& xi : sample_points(shape)) {
      const auto n = shape_functions(shape, xi);
      double sum = 0.0;
      for (double v : n) sum += v;
      EXPECT_NEAR(sum, 1.0, 1e-15);
      const auto d = shape_derivatives(shape, xi);
      EXPECT_NEAR(d.col(0).sum(), 0.0, 1e-15);
      EXPECT_NEAR(d.col(1).sum(), 0.0, 1e-15);
    }
  }
}

TEST(Element, ReproducesLinearFieldsAndTheirGradients) {
  // u(x) = a + b·x must be interpolated and differentiated exactly on any element.
  const double a = 0.7;
  const Vec2 b(-1.3, 2.1);
  for (auto shape : shapes) {
    const ElementNodes x = distorted_nodes(shape);
    Eigen::Vector4d u = Eigen::Vector4d::Zero();
    for (int k = 0; k < nodes_per_element(shape); ++k) u[k] = a + b.dot(x.row(k).transpose());
    for (const auto& xi : sample_points(shape)) {
      const auto n = shape_functions(shape, xi);
      const Vec2 point = map_to_physical(shape, x, xi);
      double interpolated = 0.0;
      for (int k = 0; k < 4; ++k) interpolated += n[static_cast<std::size_t>(k)] * u[k];
      EXPECT_NEAR(interpolated, a + b.dot(point), 1e-14);
      double det = 0.0;
      const ShapeGradients g = physical_gradients(shape, x, xi, &det);
      EXPECT_GT(det, 0.0);
      const Vec2 gradient = g.transpose() * u;
      EXPECT_NEAR(gradient.x(), b.x(), 1e-13);
      EXPECT_NEAR(gradient.y(), b.y(), 1e-13);
    }
  }
}

TEST(Element, SolverRulesIntegrateTheAreaExactly) {
  for (auto type : {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    const auto shape = shape_of(type);
    const ElementNodes x = distorted_nodes(shape);
    double area = 0.0, weights = 0.0;
    for (const auto& q : quadrature_rule(type)) {
      area += q.weight * jacobian(shape, x, q.xi).determinant();
      weights += q.weight;
    }
    EXPECT_NEAR(weights, reference_measure(shape), 1e-15);
    // det J is linear in ξ, η on a quad: every rule here integrates it exactly.
    EXPECT_NEAR(area, element_area(shape, x), 1e-14);
  }
}

TEST(GaussLegendre, IntegratesPolynomialsOfDegree2nMinus1Exactly) {
  for (int order = 1; order <= 12; ++order) {
    const auto rule = gauss_legendre(order);
    for (int degree = 0; degree <= 2 * order - 1; ++degree) {
      double sum = 0.0;
      for (std::size_t i = 0; i < rule.points.size(); ++i) {
        sum += rule.weights[i] * std::pow(rule.points[i], degree);
      }
      const double exact = degree % 2 == 1 ? 0.0 : 2.0 / (degree + 1);
      EXPECT_NEAR(sum, exact, 1e-14) << "order " << order << " degree " << degree;
    }
    // ... and no more: the error on x^(2n) (1.8e-7 at n = 12) stands far above round-off.
    double sum = 0.0;
    for (std::size_t i = 0; i < rule.points.size(); ++i) {
      sum += rule.weights[i] * std::pow(rule.points[i], 2 * order);
    }
    EXPECT_GT(std::abs(sum - 2.0 / (2 * order + 1)), 1e-10) << "order " << order;
  }
}

TEST(GaussLegendre, TensorRuleOrdersXiFastestAndWeightsSumToFour) {
  const auto rule = tensor_gauss_legendre(3, 2);
  ASSERT_EQ(rule.size(), 6u);
  double weights = 0.0;
  for (const auto& q : rule) weights += q.weight;
  EXPECT_NEAR(weights, 4.0, 1e-14);
  EXPECT_LT(rule[0].xi.x(), rule[1].xi.x());
  EXPECT_DOUBLE_EQ(rule[0].xi.y(), rule[2].xi.y());
  EXPECT_LT(rule[2].xi.y(), rule[3].xi.y());
}

}  // namespace
}  // namespace slide
