// Multiquadric RBF interpolation: passes through its data, reproduces linear fields
// exactly with the linear polynomial (also by extrapolation), survives collinear
// centres, refuses what does not fit in memory, and is deterministic.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <omp.h>

#include "common/base/error.hpp"
#include "transfer/rbf_interpolation.hpp"

namespace slide::transfer {
namespace {

/// Scattered centres: a jittered grid over [0, 3] × [0, 2].
std::vector<Vec2> scattered_centres(int nx, int ny, unsigned seed = 7) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<Vec2> centres;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      centres.emplace_back((i + 0.5 + jitter(random)) * 3.0 / nx,
                           (j + 0.5 + jitter(random)) * 2.0 / ny);
    }
  }
  return centres;
}

/// Three components: a smooth non-linear field, a linear one and a constant.
FieldValues sample(std::span<const Vec2> points) {
  FieldValues values(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec2& x = points[i];
    const auto r = static_cast<Eigen::Index>(i);
    values(r, 0) = std::sin(1.7 * x.x()) * std::cos(1.3 * x.y());
    values(r, 1) = -2.5e4 + 1.2e4 * x.x() - 3.4e4 * x.y();
    values(r, 2) = 3.0;
  }
  return values;
}

/// Points inside and well outside the cloud (extrapolation by up to half its size).
std::vector<Vec2> probes() {
  std::vector<Vec2> points;
  for (int j = 0; j <= 10; ++j) {
    for (int i = 0; i <= 10; ++i) points.emplace_back(-1.0 + 0.5 * i, -1.0 + 0.4 * j);
  }
  return points;
}

constexpr std::size_t plenty = std::size_t{1} << 30;

TEST(RbfInterpolation, DefaultShapeParameterIsTheMeanSpacing) {
  std::vector<Vec2> grid;
  for (int j = 0; j < 5; ++j) {
    for (int i = 0; i < 8; ++i) grid.emplace_back(0.5 * i, 0.5 * j);
  }
  // Box 3.5 × 2 over 40 points.
  EXPECT_DOUBLE_EQ(default_shape_parameter(grid), std::sqrt(3.5 * 2.0 / 40.0));
  const std::vector<Vec2> line{{0.0, 1.0}, {1.0, 1.0}, {2.0, 1.0}, {4.0, 1.0}};
  EXPECT_DOUBLE_EQ(default_shape_parameter(line), 1.0);
}

TEST(RbfInterpolation, DenseInterpolatesItsDataWithOneFactorisation) {
  const auto centres = scattered_centres(12, 9);
  const FieldValues values = sample(centres);
  for (auto polynomial : {RbfPolynomial::none, RbfPolynomial::linear}) {
    const DenseRbf rbf(centres, values, default_shape_parameter(centres), polynomial, plenty);
    EXPECT_EQ(rbf.diagnostics().factorisations, 1u);
    EXPECT_GT(rbf.diagnostics().condition_estimate, 1.0);
    const FieldValues at_centres = rbf.evaluate(centres);
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      const double scale = values.col(c).cwiseAbs().maxCoeff();
      EXPECT_LT((at_centres.col(c) - values.col(c)).cwiseAbs().maxCoeff(), 1e-8 * scale);
    }
  }
}

TEST(RbfInterpolation, LinearPolynomialReproducesLinearFieldsAlsoOutside) {
  const auto centres = scattered_centres(12, 9);
  const FieldValues values = sample(centres);
  const auto points = probes();
  const FieldValues exact = sample(points);
  const double scale = exact.col(1).cwiseAbs().maxCoeff();
  const double c = default_shape_parameter(centres);

  const DenseRbf dense(centres, values, c, RbfPolynomial::linear, plenty);
  const FieldValues by_dense = dense.evaluate(points);
  EXPECT_LT((by_dense.col(1) - exact.col(1)).cwiseAbs().maxCoeff(), 1e-9 * scale);
  EXPECT_LT((by_dense.col(2) - exact.col(2)).cwiseAbs().maxCoeff(), 1e-9 * 3.0);

  for (int k : {3, 8, 16, 40}) {
    const FieldValues by_local =
        interpolate_local_rbf(centres, values, points, {c, RbfPolynomial::linear, k});
    EXPECT_LT((by_local.col(1) - exact.col(1)).cwiseAbs().maxCoeff(), 1e-9 * scale) << k;
    EXPECT_LT((by_local.col(2) - exact.col(2)).cwiseAbs().maxCoeff(), 1e-9 * 3.0) << k;
  }

  // The plain multiquadric does not reproduce a linear field away from its data.
  const DenseRbf plain(centres, values, c, RbfPolynomial::none, plenty);
  EXPECT_GT((plain.evaluate(points).col(1) - exact.col(1)).cwiseAbs().maxCoeff(), 1e-6 * scale);
}

TEST(RbfInterpolation, LocalWithAllCentresEqualsDense) {
  const auto centres = scattered_centres(6, 5);
  const FieldValues values = sample(centres);
  const auto points = probes();
  const double c = default_shape_parameter(centres);
  for (auto polynomial : {RbfPolynomial::none, RbfPolynomial::linear}) {
    const FieldValues dense = DenseRbf(centres, values, c, polynomial, plenty).evaluate(points);
    RbfDiagnostics diagnostics;
    const FieldValues local = interpolate_local_rbf(
        centres, values, points, {c, polynomial, static_cast<int>(centres.size())}, &diagnostics);
    // One neighbourhood (all centres) for every point: one factorisation per thread.
    EXPECT_LE(diagnostics.factorisations, static_cast<std::size_t>(omp_get_max_threads()));
    EXPECT_LT((dense - local).cwiseAbs().maxCoeff(), 1e-8 * values.cwiseAbs().maxCoeff());
  }
}

TEST(RbfInterpolation, CollinearCentresReduceTheLinearPolynomialToAConstant) {
  std::vector<Vec2> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(0.5, 0.25 * i);
  const FieldValues values = sample(line);
  const std::vector<Vec2> points{{0.5, 0.3}, {0.2, 1.1}, {0.9, 2.0}};
  const DenseRbf dense(line, values, default_shape_parameter(line), RbfPolynomial::linear, plenty);
  EXPECT_EQ(dense.diagnostics().reduced_polynomial, 1u);
  EXPECT_TRUE(dense.evaluate(points).allFinite());
  RbfDiagnostics diagnostics;
  const FieldValues local = interpolate_local_rbf(
      line, values, points, {default_shape_parameter(line), RbfPolynomial::linear, 4},
      &diagnostics);
  EXPECT_GT(diagnostics.reduced_polynomial, 0u);
  EXPECT_TRUE(local.allFinite());
}

TEST(RbfInterpolation, DenseRefusesWhatDoesNotFitAndRecommendsRbfLocal) {
  const auto centres = scattered_centres(10, 10);
  const FieldValues values = sample(centres);
  EXPECT_EQ(dense_rbf_bytes(100, RbfPolynomial::none), 100u * 100u * 8u);
  EXPECT_EQ(dense_rbf_bytes(100, RbfPolynomial::linear), 103u * 103u * 8u);
  try {
    const DenseRbf rbf(centres, values, 0.2, RbfPolynomial::none, 50'000);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("rbf-local"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(RbfInterpolation, LocalIsBitIdenticalForAnyThreadCount) {
  const auto centres = scattered_centres(30, 20);
  const FieldValues values = sample(centres);
  const auto points = scattered_centres(90, 60, 11);
  const LocalRbfOptions options{default_shape_parameter(centres), RbfPolynomial::linear, 16};
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const FieldValues one = interpolate_local_rbf(centres, values, points, options);
  omp_set_num_threads(std::max(threads, 2));
  const FieldValues two = interpolate_local_rbf(centres, values, points, options);
  omp_set_num_threads(threads);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(
      std::memcmp(one.data(), two.data(), static_cast<std::size_t>(one.size()) * sizeof(double)),
      0);
}

}  // namespace
}  // namespace slide::transfer
