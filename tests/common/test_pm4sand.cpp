// PM4Sand (common/physics/pm4sand.hpp) and the element tests that calibrate it
// (common/physics/element_test.hpp), against what can be derived or is stated exactly:
//  - every secondary constant against its formula of the report, and the constants fixed
//    at the switch (z_max, A_do, p_min) from the point's p₀;
//  - the elastic shear modulus G = G₀ p_A sqrt(p/p_A) at isotropic stress, measured from a
//    small shear increment;
//  - drained monotonic simple shear of a dense sand peaks at the bounding ratio M_b of
//    its state (φ_peak = asin(M_b/2)) and tends to the critical ratio M_c at large strain;
//  - undrained cyclic simple shear with h_po calibrated to the Idriss–Boulanger CRR
//    reaches 3 % strain in 15 ± 1 cycles at CSR = CRR (D_R = 0.35, 0.55, 0.75); halving
//    the strain step or the sub-increment changes those cycles by less than 2 %;
//  - p′ never falls below the model's floor p_min/5, and 10⁶ random strain increments
//    give finite stresses and states;
//  - the objective rotation turns the tensor records and leaves the scalars.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "common/physics/constitutive.hpp"
#include "common/physics/element_test.hpp"
#include "common/physics/pm4sand.hpp"
#include "tests/support/material_point.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide {
namespace {

using element_test::Consolidation;
using element_test::Drainage;

constexpr double p_a = 101.3e3;

/// A point switched at `stress` (tension positive).
testing::MaterialPoint switched(const Material& m, const Vec4& stress) {
  testing::MaterialPoint point(m, stress);
  point.start();
  return point;
}

TEST(Pm4Sand, SecondaryConstantsFollowTheirFormulas) {
  for (double dr : {0.35, 0.55, 0.75, 0.9}) {
    SCOPED_TRACE(dr);
    const pm4sand::Constants c = pm4sand::Constants::of(synthetic::sand(dr, 0.5));
    EXPECT_DOUBLE_EQ(c.g0, 167.0 * std::sqrt(46.0 * dr * dr + 2.5));
    EXPECT_DOUBLE_EQ(c.h0, std::max(0.3, (0.25 + dr) / 2.0));
    EXPECT_DOUBLE_EQ(c.e0, 0.8 - 0.3 * dr);
    EXPECT_DOUBLE_EQ(c.c_dr, std::min(5.0 + 25.0 * (dr - 0.35), 10.0));
    EXPECT_DOUBLE_EQ(c.c_kaf, std::clamp(5.0 + 220.0 * std::pow(dr - 0.26, 3), 4.0, 35.0));
    const double c_e = dr > 0.75 ? 0.2 : (dr < 0.55 ? 0.5 : 0.5 - 1.5 * (dr - 0.55));
    EXPECT_DOUBLE_EQ(c.c_e, c_e);
    EXPECT_DOUBLE_EQ(c.m_c, 2.0 * std::sin(33.0 * std::numbers::pi / 180.0));
    EXPECT_DOUBLE_EQ(c.bulk_ratio(), 2.0 * 1.3 / (3.0 * 0.4));
  }
}

TEST(Pm4Sand, TheSwitchFixesTheStressDependentConstantsFromP0) {
  // K0 = 0.5 at σ′v = 1 atm: p₀ = 0.75 atm.
  const Material m = synthetic::sand(0.55, 0.5);
  const auto point = switched(m, {-0.5 * p_a, -p_a, -0.5 * p_a, 0.0});
  const pm4sand::Constants c = pm4sand::Constants::of(m);
  const double p0 = 0.75 * p_a;
  const double xi = 1.5 / (10.0 - std::log(100.0 * p0 / p_a)) - 0.55;
  const double m_b = c.m_c * std::exp(-0.5 * xi);
  const double m_d = c.m_c * std::exp(0.1 * xi);
  const Vec4& constants = point.surfaces[pm4sand::switch_constants];
  EXPECT_DOUBLE_EQ(constants[0], std::min(0.7 * std::exp(-6.1 * xi), 20.0));  // z_max
  EXPECT_NEAR(constants[1], 2.5 * (std::asin(m_b / 2.0) - std::asin(c.m_c / 2.0)) / (m_b - m_d),
              1e-12);                                                 // A_do
  EXPECT_DOUBLE_EQ(constants[2], std::max(p0 / 200.0, p_a / 200.0));  // p_min
  // α = s/p₀ of the in-plane stress (compression positive), σzz on the in-plane mean.
  const Vec4& alpha = point.surfaces[pm4sand::back_stress];
  EXPECT_NEAR(alpha[0], (0.5 * p_a - p0) / p0, 1e-14);
  EXPECT_NEAR(alpha[1], (p_a - p0) / p0, 1e-14);
  EXPECT_DOUBLE_EQ(point.stress[2], -p0);
}

TEST(Pm4Sand, ElasticShearModulusGrowsWithTheSquareRootOfP) {
  const Material m = synthetic::sand(0.55, 0.5);
  const double g0 = pm4sand::Constants::of(m).g0;
  for (double p : {25e3, 101.3e3, 400e3}) {
    SCOPED_TRACE(p);
    auto point = switched(m, {-p, -p, -p, 0.0});
    const double expected = g0 * p_a * std::sqrt(p / p_a);
    EXPECT_NEAR(pm4sand::shear_modulus(pm4sand::Constants::of(m), point.stress, point.surfaces),
                expected, 1e-12 * expected);
    // A shear increment far inside the yield surface (radius m p/√2 ≈ 0.7 % of p).
    const double d_gamma = 1e-7;
    point.step({0.0, 0.0, 0.0, d_gamma});
    EXPECT_NEAR(point.stress[3] / d_gamma, expected, 1e-6 * expected);
  }
}

TEST(Pm4Sand, DrainedSimpleShearPeaksAtTheBoundingRatioAndEndsAtCriticalState) {
  const Material m = synthetic::sand(0.75, 0.8);
  const pm4sand::Constants c = pm4sand::Constants::of(m);
  const auto history = element_test::monotonic(m, Consolidation{}, Drainage::drained, 2.0, 4e-4);
  std::size_t peak = 0;
  for (std::size_t i = 0; i < history.size(); ++i) {
    if (history[i].stress_ratio > history[peak].stress_ratio) peak = i;
  }
  // M_b of the state at the peak: its p and its D_R (moved by the dilation so far).
  const element_test::Sample& s = history[peak];
  const double e = c.e0 - (1.0 + c.e0) * s.volumetric_strain;
  const double dr = (c.e_max - e) / (c.e_max - c.e_min);
  const double m_b = pm4sand::ratios(c, s.mean_stress, dr).bounding;
  const double phi_peak = std::asin(s.stress_ratio / 2.0);
  std::printf(
      "drained D_R 0.75: peak q/p %.4f at gamma %.4f, M_b there %.4f; phi_peak %.2f "
      "against asin(M_b/2) %.2f degrees; q/p at gamma 2: %.4f, M_c %.4f\n",
      s.stress_ratio, s.shear_strain, m_b, phi_peak * 180 / std::numbers::pi,
      std::asin(m_b / 2.0) * 180 / std::numbers::pi, history.back().stress_ratio, c.m_c);
  EXPECT_NEAR(s.stress_ratio, m_b, 2e-3 * m_b);
  EXPECT_GT(m_b, 1.2 * c.m_c);  // a dense sand: the peak is well above critical
  // After the peak the ratio falls toward M_c as the sand dilates to critical state.
  EXPECT_LT(history.back().stress_ratio, history[peak].stress_ratio);
  EXPECT_NEAR(history.back().stress_ratio, c.m_c, 0.01 * c.m_c);
  EXPECT_LT(history.back().volumetric_strain, -0.05);  // dilated
}

/// Cycles to 3 % strain at CSR = CRR with the h_po that the calibration finds.
struct Calibrated {
  double contraction_rate;
  double cycles;
};

Calibrated calibrated(double dr) {
  const double crr = element_test::idriss_boulanger_crr(pm4sand::blow_count(dr));
  Material m = synthetic::sand(dr, 1.0);
  const auto cal = element_test::calibrate_contraction_rate(m, crr);
  m.pm4sand.contraction_rate = cal.contraction_rate;
  const auto r = element_test::cyclic(m, Consolidation{p_a, 0.5}, crr, 60.0, 0.03, 1e-5, 1000);
  return {cal.contraction_rate, r.cycles_to_strain};
}

TEST(Pm4Sand, CalibratedSandsLiquefyInFifteenCyclesAtTheirCrr) {
  // METHOD §10's CRR values for the Idriss–Boulanger curve at (N1)60cs = 46 D_R².
  const std::array<std::pair<double, double>, 3> targets{
      {{0.35, 0.090}, {0.55, 0.147}, {0.75, 0.312}}};
  for (const auto& [dr, crr] : targets) {
    SCOPED_TRACE(dr);
    EXPECT_NEAR(element_test::idriss_boulanger_crr(pm4sand::blow_count(dr)), crr, 5e-4);
    const Calibrated c = calibrated(dr);
    std::printf("D_R %.2f: CRR %.4f, calibrated h_po %.4f, cycles to 3 %% strain %.3f\n", dr,
                element_test::idriss_boulanger_crr(pm4sand::blow_count(dr)), c.contraction_rate,
                c.cycles);
    EXPECT_NEAR(c.cycles, 15.0, 1.0);
    EXPECT_GT(c.contraction_rate, 0.05);
    EXPECT_LT(c.contraction_rate, 5.0);
  }
}

TEST(Pm4Sand, CyclesToLiquefactionDoNotDependOnTheStep) {
  const Material base = synthetic::sand(0.55, 0.45);
  const double csr = 0.147;
  auto cycles = [&](double d_gamma, double strain_step) {
    Material m = base;
    m.pm4sand.strain_step = strain_step;
    return element_test::cyclic(m, Consolidation{}, csr, 60.0, 0.03, d_gamma, 1000)
        .cycles_to_strain;
  };
  const double reference = cycles(1e-5, 1e-5);
  const double half_step = cycles(5e-6, 1e-5);
  const double half_sub = cycles(2e-5, 5e-6);
  const double coarse = cycles(2e-5, 1e-5);
  std::printf(
      "cycles to 3 %% strain: %.4f (dgamma 1e-5), %.4f (5e-6), %.4f (2e-5, sub-increment "
      "5e-6), %.4f (2e-5)\n",
      reference, half_step, half_sub, coarse);
  for (double other : {half_step, half_sub, coarse})
    EXPECT_NEAR(other, reference, 0.02 * reference);
}

TEST(Pm4Sand, EffectiveStressNeverFallsBelowTheFloor) {
  const Material m = synthetic::sand(0.35, 0.4);
  const auto r = element_test::cyclic(m, Consolidation{}, 0.12, 40.0, 0.2, 1e-5, 1);
  ASSERT_FALSE(std::isnan(r.cycles_to_strain));
  double smallest = INFINITY;
  for (const auto& s : r.history) smallest = std::min(smallest, s.mean_stress);
  const double p_min = std::max(0.75 * p_a / 200.0, p_a / 200.0);
  std::printf(
      "deep cyclic mobility (gamma to 20 %%): r_u max %.4f, smallest p' %.1f Pa, floor "
      "p_min/5 = %.1f Pa\n",
      r.max_pore_pressure_ratio, smallest, p_min / 5.0);
  EXPECT_GT(r.max_pore_pressure_ratio, 0.95);
  EXPECT_GE(smallest, p_min / 5.0 * (1.0 - 1e-9));
}

TEST(Pm4Sand, RandomStrainPathsStayFinite) {
  std::mt19937_64 random(20261205);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> density(0.3, 0.9);
  std::size_t increments = 0;
  for (int path = 0; path < 1000; ++path) {
    const Material m = synthetic::sand(density(random), 0.1 + 0.9 * (unit(random) + 1.0));
    const double p = p_a * (0.05 + 3.0 * (unit(random) + 1.0));
    auto point = switched(m, {-p * (0.5 + 0.4 * unit(random)), -p, -p, 0.2 * p * unit(random)});
    // Mostly shear, with volume changes of either sign (extension included), sizes
    // spanning four decades.
    for (int k = 0; k < 1000; ++k, ++increments) {
      const double size = std::pow(10.0, -7.0 + 3.0 * (unit(random) + 1.0) / 2.0);
      const Vec4 d{size * unit(random) * 0.3, size * unit(random) * 0.3, 0.0, size * unit(random)};
      point.step(d);
      bool finite = point.stress.allFinite() && std::isfinite(point.state.plastic_shear_strain);
      for (const Vec4& r : point.surfaces) finite = finite && r.allFinite();
      ASSERT_TRUE(finite) << "path " << path << ", increment " << k;
      ASSERT_GE(-0.5 * (point.stress[0] + point.stress[1]),
                point.surfaces[pm4sand::switch_constants][2] / 5.0 * (1.0 - 1e-9));
    }
  }
  EXPECT_EQ(increments, 1000000u);
}

TEST(Pm4Sand, ObjectiveRotationTurnsTheTensorRecordsOnly) {
  const Material m = synthetic::sand(0.55, 0.5);
  auto point = switched(m, {-0.5 * p_a, -p_a, -0.5 * p_a, 0.1 * p_a});
  const std::vector<Vec4> before = point.surfaces;
  point.model.rotate_records(point.surfaces, 0.01);
  for (int k = pm4sand::back_stress; k <= pm4sand::fabric_at_reversal; ++k) {
    Vec4 turned = before[static_cast<std::size_t>(k)];
    rotate_jaumann(turned, 0.01);
    EXPECT_EQ(point.surfaces[static_cast<std::size_t>(k)], turned);
  }
  EXPECT_EQ(point.surfaces[pm4sand::fabric_measures], before[pm4sand::fabric_measures]);
  EXPECT_EQ(point.surfaces[pm4sand::switch_constants], before[pm4sand::switch_constants]);
}

}  // namespace
}  // namespace slide
