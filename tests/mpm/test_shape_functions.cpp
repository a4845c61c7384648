// The 1-D shape functions: partition of unity, reproduction of linear fields, uGIMP equal
// to the hat function averaged over the particle domain (its definition), and APIC's
// moments: D = Σ S_k (k − ξ)² and the affine weights e_k = S_k (k − ξ)/D.
#include <cmath>
#include <tuple>

#include <gtest/gtest.h>

#include "mpm/shape_functions.hpp"
#include "tests/support/same_bits.hpp"

namespace slide::mpm {
namespace {

double hat(double r) {
  return std::max(0.0, 1.0 - std::abs(r));
}

template <class Shape>
void check_partition_and_linear_reproduction(double xi, double a) {
  const auto w = Shape::weights(xi, a);
  double sum = 0.0, first = 0.0, slope_sum = 0.0, slope_first = 0.0;
  for (int k = 0; k < Shape::support; ++k) {
    const double node = w.base + k;
    sum += w.value[k];
    first += w.value[k] * node;
    slope_sum += w.derivative[k];
    slope_first += w.derivative[k] * node;
    EXPECT_GE(w.value[k], -1e-15);
  }
  EXPECT_NEAR(sum, 1.0, 1e-14) << xi;
  EXPECT_NEAR(first, xi, 1e-13) << xi;  // Σ S_k x_k = x_p
  EXPECT_NEAR(slope_sum, 0.0, 1e-14) << xi;
  EXPECT_NEAR(slope_first, 1.0, 1e-13) << xi;  // Σ S'_k x_k = 1
}

TEST(ShapeFunctions, PartitionOfUnityAndLinearReproduction) {
  for (double xi = 0.0; xi < 6.0; xi += 0.01237) {
    check_partition_and_linear_reproduction<LinearShape>(xi, 0.0);
    for (double a : {0.05, 0.125, 0.25, 0.5})
      check_partition_and_linear_reproduction<GimpShape>(xi, a);
  }
}

TEST(ShapeFunctions, GimpIsTheHatAveragedOverTheParticleDomain) {
  for (double a : {0.125, 0.3, 0.5}) {
    for (double xi = 2.0; xi < 4.0; xi += 0.0371) {
      const auto w = GimpShape::weights(xi, a);
      for (int k = 0; k < 3; ++k) {
        const double node = w.base + k;
        // Midpoint rule over [ξ − a, ξ + a] with many points.
        const int n = 20000;
        double average = 0.0, slope = 0.0;
        for (int i = 0; i < n; ++i) {
          const double s = xi - a + (i + 0.5) * 2 * a / n;
          average += hat(s - node) / n;
        }
        slope = (hat(xi + a - node) - hat(xi - a - node)) / (2 * a);  // d/dξ of the average
        EXPECT_NEAR(w.value[k], average, 1e-8) << "xi " << xi << " a " << a;
        EXPECT_NEAR(w.derivative[k], slope, 1e-12) << "xi " << xi << " a " << a;
      }
      // The nodes just outside the stencil get nothing: the domain does not reach them.
      for (const double outside : {w.base - 1.0, w.base + 3.0}) {
        EXPECT_GE(std::abs(xi - outside), 1.0 + a - 1e-12) << "xi " << xi << " a " << a;
      }
    }
  }
}

/// The moments `affine` returns against their definitions, and the two identities APIC
/// rests on: Σ_k e_k = 0 and Σ_k e_k (k − ξ) = 1 (C_p = Σ v_i e_iᵀ then returns the slope
/// of any linear field, and nothing of a constant one).
template <class Shape>
void check_affine_moments(double xi, double a) {
  const auto w = Shape::weights(xi, a);
  const auto m = Shape::affine(w, xi);
  double inertia = 0.0, sum = 0.0, first = 0.0;
  for (int k = 0; k < Shape::support; ++k) {
    const double d = w.base + k - xi;
    inertia += w.value[k] * d * d;
    EXPECT_NEAR(m.moment[k], w.value[k] * d, 1e-14) << xi;
    sum += m.value[k];
    first += m.value[k] * d;
  }
  EXPECT_NEAR(m.inertia, inertia, 1e-13) << xi;
  EXPECT_EQ(Shape::inertia(xi, a), m.inertia) << xi;
  EXPECT_NEAR(sum, 0.0, 1e-12) << xi;
  if (m.inertia > 1e-9) {
    EXPECT_NEAR(first, 1.0, 1e-12) << xi;
  }
}

TEST(ShapeFunctions, ApicInertiaAndAffineWeights) {
  for (double xi = 0.0; xi < 6.0; xi += 0.01237) {
    check_affine_moments<LinearShape>(xi, 0.0);
    // Linear hats: D = f(1 − f) and e_k = dS_k/dξ exactly (no division by D).
    const auto w = LinearShape::weights(xi, 0.0);
    const auto m = LinearShape::affine(w, xi);
    const double f = xi - std::floor(xi);
    EXPECT_DOUBLE_EQ(m.inertia, f * (1.0 - f));
    EXPECT_EQ(m.value[0], w.derivative[0]);
    EXPECT_EQ(m.value[1], w.derivative[1]);
    for (double a : {0.05, 0.125, 0.25, 0.5}) {
      check_affine_moments<GimpShape>(xi, a);
      // uGIMP: between a/2 (centred on a node) and 1/4 (cell centre), never singular.
      const double d = GimpShape::inertia(xi, a);
      EXPECT_GE(d, 0.5 * a - 1e-14) << xi << " " << a;
      EXPECT_LE(d, 0.25 + 1e-14) << xi << " " << a;
    }
    // l_p = h (a = ½) is the quadratic B-spline, whose D is Jiang et al.'s h²/4 everywhere.
    EXPECT_NEAR(GimpShape::inertia(xi, 0.5), 0.25, 1e-14) << xi;
  }
  EXPECT_NEAR(GimpShape::inertia(3.0, 0.125), 0.0625, 1e-15);  // a/2 on a node
  EXPECT_NEAR(GimpShape::inertia(3.5, 0.125), 0.25, 1e-15);    // ¼ at a cell centre
}

TEST(ShapeFunctions, TheCellOfTheWeightsIsTheFloorOfThePosition) {
  // The kernels find a particle's cell (volumetric smoothing) from its weights instead of
  // flooring ξ again: base + cell must be ⌊ξ⌋ exactly, also where ξ + ½ rounds up to an
  // integer and on the node and cell-centre lines themselves.
  for (int node = -1; node <= 12; ++node) {
    for (double centre : {node - 0.5, node + 0.0, node + 0.5}) {
      double xi = centre;
      for (int ulp = 0; ulp < 4; ++ulp) xi = std::nextafter(xi, -1e9);
      for (int ulp = 0; ulp < 9; ++ulp, xi = std::nextafter(xi, 1e9)) {
        const auto gimp = GimpShape::weights(xi, 0.125);
        const auto linear = LinearShape::weights(xi, 0.125);
        EXPECT_EQ(gimp.base + gimp.cell, std::floor(xi)) << xi;
        EXPECT_EQ(linear.base + linear.cell, std::floor(xi)) << xi;
      }
    }
  }
  for (double xi = -0.5; xi < 10.5; xi += 0.0137) {
    const auto w = GimpShape::weights(xi, 0.25);
    EXPECT_EQ(w.base + w.cell, std::floor(xi)) << xi;
  }
}

// The two paths may differ in a build that contracts products and sums into FMAs
// (-march=native on an FMA machine): GCC decides per inlined copy which ones to fuse, and
// a fused one rounds once instead of twice. There they agree within 2 ulp of 1 (every
// value and moment is at most 1, e_k at most 1/D ≤ 2/a).
void expect_same(double from_pair, double from_scalar, double scale) {
  slide::testing::expect_same_bits(from_pair, from_scalar, 4.5e-16 * scale);
}

TEST(ShapeFunctions, BothAxesAtOnceGiveTheBitsOfOneAxisAtATime) {
  // The kernels compute a particle's x and y weights in the two lanes of one register
  // (pair.hpp); every lane does the one-axis function's operations in the same order, so
  // without FMA contraction the bits are the same.
  const int cells = 40;
  int checked = 0;
  for (double xi = -0.4999; xi < cells + 0.5; xi += 0.0173) {
    const double eta = cells - xi;  // the other lane elsewhere in its cell
    for (double a : {0.5, 0.25, 0.125, 0.087, 1e-3}) {
      const double ax = clipped_half_size(xi, cells, a),
                   ay = clipped_half_size(eta, cells, 0.5 * a);
      Weights2d<3> both;
      GimpShape::weights(Pair{xi, eta}, Pair{ax, ay}, both);
      AffineWeights2d<3> both_moments;
      GimpShape::affine(both, both_moments);
      const Weights1d<3> x = both.axis(0), y = both.axis(1);
      const AffineWeights1d<3> mx = both_moments.axis(both, 0), my = both_moments.axis(both, 1);
      for (const auto& [pair, moments, scalar, scalar_moments] :
           {std::tuple{x, mx, GimpShape::weights(xi, ax), GimpShape::affine(x, xi)},
            std::tuple{y, my, GimpShape::weights(eta, ay), GimpShape::affine(y, eta)}}) {
        ASSERT_EQ(pair.base, scalar.base);
        ASSERT_EQ(pair.cell, scalar.cell);
        SCOPED_TRACE(::testing::Message() << "ξ = " << xi << ", a = " << a);
        expect_same(moments.inertia, scalar_moments.inertia, 1.0);
        for (int k = 0; k < 3; ++k) {
          expect_same(pair.value[k], scalar.value[k], 1.0);
          expect_same(pair.derivative[k], scalar.derivative[k], 1.0);
          expect_same(moments.moment[k], scalar_moments.moment[k], 1.0);
          expect_same(moments.value[k], scalar_moments.value[k], 2.0 / a);
        }
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 10000);
}

TEST(ShapeFunctions, TheKernelsSkipOnlyNodesTheDomainDoesNotReach) {
  // Weights2d keeps the nodes an axis's domain [ξ − a, ξ + a] reaches: 2 where it lies
  // inside one cell (|f| ≥ a), 3 where it straddles the nearest node. Every node left out
  // must have weight and derivative exactly 0 in the one-axis weights (the kernels skip
  // it, which is bit-identical only then), and every node kept must be one the domain
  // reaches (a kept zero would only cost time; this checks the count is tight).
  const int cells = 40;
  for (double a : {0.5, 0.25, 0.125, 0.087, 1e-3}) {
    int two = 0, all = 0;
    for (double xi = -0.4999; xi < cells + 0.5; xi += 0.0173) {
      Weights2d<3> both;
      GimpShape::weights(Pair{xi, xi}, Pair{a, a}, both);
      const Weights1d<3> scalar = GimpShape::weights(xi, a);
      const int skipped = both.skipped[0], count = both.count[0];
      ASSERT_EQ(both.base[0], scalar.base + skipped);
      const double f = xi - (scalar.base + 1);
      EXPECT_EQ(count, std::abs(f) >= a ? 2 : 3) << "ξ = " << xi << ", a = " << a;
      for (int k = 0; k < 3; ++k) {
        const bool kept = k >= skipped && k < skipped + count;
        SCOPED_TRACE(::testing::Message() << "ξ = " << xi << ", a = " << a << ", node " << k);
        if (kept) {
          EXPECT_GT(scalar.value[k], 0.0);
          expect_same(both.value[k - skipped][0], scalar.value[k], 1.0);
        } else {
          EXPECT_EQ(scalar.value[k], 0.0);
          EXPECT_EQ(scalar.derivative[k], 0.0);
        }
      }
      two += count == 2 ? 1 : 0;
      ++all;
    }
    // Positions spread evenly over the cells: the domain stays inside one cell for the
    // share 1 − 2a of them (column-short's a = ⅛: three axes in four).
    EXPECT_NEAR(double(two) / all, 1.0 - 2.0 * a, 0.01) << "a = " << a;
  }
}

TEST(ShapeFunctions, AParticleInsideTheGridNeverTouchesAGhostNode) {
  // The basal artefact's cause: a uGIMP domain reaching through the base put a sliver of
  // mass, and a tenth of the gradient, on the ghost node below it. With the half-length
  // clipped at the grid's edge, every particle inside the grid gives the ghost nodes
  // (k = −1 and k = cells + 1) exactly zero weight and zero gradient, while the weights
  // keep the partition of unity and reproduce linear fields.
  const int cells = 10;
  for (double a : {0.087, 0.125, 0.25, 0.5}) {
    for (double xi = 1e-3; xi < cells - 1e-3; xi += 0.0137) {
      const double clipped = clipped_half_size(xi, cells, a);
      EXPECT_LE(clipped, a);
      const Weights1d<3> w = GimpShape::weights(xi, clipped);
      double sum = 0.0, first = 0.0, slope = 0.0;
      for (int k = 0; k < 3; ++k) {
        const int node = w.base + k;
        if (node < 0 || node > cells) {
          EXPECT_EQ(w.value[k], 0.0) << "ghost node " << node << " at ξ = " << xi << ", a = " << a;
          EXPECT_EQ(w.derivative[k], 0.0) << node << " " << xi << " " << a;
        }
        sum += w.value[k];
        first += w.value[k] * node;
        slope += w.derivative[k];
      }
      EXPECT_NEAR(sum, 1.0, 1e-14);
      EXPECT_NEAR(first, xi, 1e-13);
      EXPECT_NEAR(slope, 0.0, 1e-13);
    }
  }
  // Away from the edges the particle keeps its own domain.
  EXPECT_EQ(clipped_half_size(5.3, cells, 0.087), 0.087);
  // column-short's lowest row: 0.069 h above the base, a = 0.087 clipped to 0.069.
  EXPECT_NEAR(clipped_half_size(0.069, cells, 0.087), 0.069, 1e-15);
}

}  // namespace
}  // namespace slide::mpm
