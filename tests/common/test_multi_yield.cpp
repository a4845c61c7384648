// Pressure-independent multi-yield plasticity (common/physics/multi_yield.hpp) against closed
// forms computed here, independently of the model's own backbone code:
//  - the frozen strength is OpenSees's calibration q_f = M p′₀ + 3c/√2 (2c for φ = 0);
//  - monotonic simple shear and triaxial (isochoric) paths follow the piecewise-linear
//    backbone through its vertices, which lie on the hyperbola τ = Gγ/(1 + γ/γ_r) shifted
//    by the first surface's offset, and stay at q_f beyond γ_peak;
//  - unloading starts elastic with G, and unloading and reloading follow Masing's rule
//    τ = τ_r ± 2 f(|γ − γ_r| / 2) about each reversal point;
//  - one surface is exactly elastic–perfectly-plastic von Mises (a radial return written
//    here) on a random strain path with volume changes;
//  - a change of confinement after the switch leaves the strength unchanged;
//  - the switch scales a stress outside the frozen surface onto it and leaves one inside
//    as it is.
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "common/physics/constitutive.hpp"
#include "common/physics/multi_yield.hpp"
#include "tests/support/material_point.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide {
namespace {

constexpr double degree = std::numbers::pi / 180.0;

Material soil(int surfaces, double phi = 22.2, double cohesion = 1000.0) {
  Material m = synthetic::material("soil", MaterialModel::pressure_independent_multi_yield, 1700.0,
                                   23.8e6, 0.23, phi, cohesion);
  m.peak_shear_strain = 0.1;
  m.yield_surfaces = surfaces;
  return m;
}

double shear_modulus(const Material& m) {
  return m.youngs_modulus / (2.0 * (1.0 + m.poisson_ratio));
}

/// q_f of OpenSees's calibration, from φ, c and p′₀.
double calibrated_strength(const Material& m, double p0) {
  const double s = std::sin(m.friction_angle * degree);
  if (s == 0.0) return 2.0 * m.cohesion;
  return 6.0 * s / (3.0 - s) * p0 + 3.0 * m.cohesion / std::numbers::sqrt2;
}

/// The backbone in (εq, q), vertex by vertex, from the hyperbola: τ, γ octahedral,
/// τ = √2/3 q, γ = √2 εq.
std::vector<std::array<double, 2>> backbone(const Material& m, double q_f) {
  const double g = shear_modulus(m);
  const int n = m.yield_surfaces;
  const double tau_f = std::numbers::sqrt2 / 3.0 * q_f;
  const double gamma_r = m.peak_shear_strain * tau_f / (g * m.peak_shear_strain - tau_f);
  auto hyperbola_strain = [&](double tau) { return tau * gamma_r / (g * gamma_r - tau); };
  const double tau_1 = tau_f / n;
  std::vector<std::array<double, 2>> vertices{{0.0, 0.0}};
  for (int i = 1; i <= n; ++i) {
    const double tau = i * tau_f / n;
    const double gamma = tau_1 / g + hyperbola_strain(tau) - hyperbola_strain(tau_1);
    vertices.push_back({gamma / std::numbers::sqrt2, 3.0 / std::numbers::sqrt2 * tau});
  }
  return vertices;
}

/// q of the backbone at εq (linear between vertices, q_f beyond the last).
double backbone_q(const std::vector<std::array<double, 2>>& v, double eps) {
  for (std::size_t i = 1; i < v.size(); ++i) {
    if (eps <= v[i][0]) {
      return v[i - 1][1] + (v[i][1] - v[i - 1][1]) * (eps - v[i - 1][0]) / (v[i][0] - v[i - 1][0]);
    }
  }
  return v.back()[1];
}

/// A point of the model: stress, state and its surfaces.
using Point = testing::MaterialPoint;

const Vec4 isotropic(-200e3, -200e3, -200e3, 0.0);  // p′ = 200 kPa

TEST(MultiYield, TheFrozenStrengthIsOpenSeesCalibrationToMohrCoulomb) {
  for (const double phi : {22.2, 35.0, 0.0}) {
    const Material m = soil(20, phi, 5e3);
    Point point(m, Vec4(-100e3, -300e3, -200e3, 20e3));  // p′₀ = 200 kPa
    point.start();
    EXPECT_NEAR(point.state.peak_strength, calibrated_strength(m, 200e3), 1e-9 * 200e3) << phi;
  }
  // A tensile mean stress freezes the strength of zero confinement.
  const Material m = soil(20);
  Point tension(m, Vec4(10e3, 10e3, 10e3, 0.0));
  tension.start();
  EXPECT_NEAR(tension.state.peak_strength, 3.0 * 1000.0 / std::numbers::sqrt2, 1e-9);
}

/// Drives a monotonic isochoric path in `direction` (a deviatoric strain increment per
/// step) and compares q with the backbone at every step.
void expect_backbone(const Vec4& direction, double eps_q_per_step, const char* path,
                     int surfaces = 20) {
  const Material m = soil(surfaces);
  Point point(m, isotropic);
  ASSERT_FALSE(point.start());
  const double q_f = point.state.peak_strength;
  const auto vertices = backbone(m, q_f);
  const Vec4 increment = direction * (eps_q_per_step / deviatoric_strain(direction));
  Vec4 strain = Vec4::Zero();
  double worst = 0.0;
  bool at_peak = false;
  for (int k = 0; k < 4000; ++k) {
    at_peak = point.step(increment);
    strain += increment;
    const double eps = deviatoric_strain(strain);
    worst = std::max(worst, std::abs(von_mises_stress(point.stress) - backbone_q(vertices, eps)));
    EXPECT_NEAR(mean_stress(point.stress), 200e3, 1e-6) << "isochoric: p′ stays";
  }
  EXPECT_GT(deviatoric_strain(strain), vertices.back()[0]) << "the path passed γ_peak";
  EXPECT_LT(worst, 1e-9 * q_f) << path;
  EXPECT_TRUE(at_peak);
  EXPECT_NEAR(von_mises_stress(point.stress), q_f, 1e-9 * q_f) << path;
}

TEST(MultiYield, SimpleShearFollowsTheBackboneThroughItsVerticesToThePeak) {
  expect_backbone(Vec4(0.0, 0.0, 0.0, 1.0), 2.5e-5, "simple shear");
  // The vertices sit on the hyperbola shifted in strain by the first surface's offset
  // δ = γ_1 − τ_1/G (elastic up to τ_1, the hyperbola's secants after): for 20 surfaces
  // δ is 2·10⁻⁴ of γ_peak.
  const Material m = soil(20);
  const double g = shear_modulus(m);
  const double tau_f = std::numbers::sqrt2 / 3.0 * calibrated_strength(m, 200e3);
  const double gamma_r = m.peak_shear_strain * tau_f / (g * m.peak_shear_strain - tau_f);
  const double tau_1 = tau_f / m.yield_surfaces;
  const double offset = tau_1 * gamma_r / (g * gamma_r - tau_1) - tau_1 / g;
  EXPECT_LT(offset, 3e-4 * m.peak_shear_strain);
}

TEST(MultiYield, TriaxialCompressionFollowsTheSameBackbone) {
  // Isochoric axial compression in y with equal lateral strains in x and z.
  expect_backbone(Vec4(0.5, -1.0, 0.5, 0.0), 2.5e-5, "triaxial");
}

TEST(MultiYield, AnOddNumberOfSurfacesFollowsItsBackbone) {
  // The update takes the components two at a time; an odd count leaves one on its own.
  expect_backbone(Vec4(0.0, 0.0, 0.0, 1.0), 2.5e-5, "simple shear, 7 surfaces", 7);
  expect_backbone(Vec4(0.5, -1.0, 0.5, 0.0), 2.5e-5, "triaxial, 3 surfaces", 3);
}

TEST(MultiYield, UnloadingIsElasticWithGAndLoopsFollowMasingsRule) {
  const Material m = soil(20);
  const double g = shear_modulus(m);
  Point point(m, isotropic);
  point.start();
  const auto vertices = backbone(m, point.state.peak_strength);
  // The backbone in simple shear: τ = q/√3 at γ = √3 εq.
  auto f = [&](double gamma) {
    return backbone_q(vertices, gamma / std::sqrt(3.0)) / std::sqrt(3.0);
  };
  const double dg = 1e-5;
  double gamma = 0.0;
  auto shear = [&](double d) {
    point.step(Vec4(0.0, 0.0, 0.0, d));
    gamma += d;
    return point.stress[3];
  };
  while (gamma < 0.02 - 0.5 * dg) shear(dg);  // to γ_a = 2 %, past several vertices
  const double gamma_a = gamma, tau_a = point.stress[3];
  EXPECT_NEAR(tau_a, f(gamma_a), 1e-9 * tau_a);
  // Unloading: elastic with G at first, then τ = τ_a − 2 f((γ_a − γ)/2).
  const double first = shear(-dg);
  EXPECT_NEAR((tau_a - first) / dg, g, 1e-6 * g);
  double worst = 0.0;
  while (gamma > -gamma_a + 0.5 * dg) {
    const double tau = shear(-dg);
    worst = std::max(worst, std::abs(tau - (tau_a - 2.0 * f((gamma_a - gamma) / 2.0))));
  }
  const double tau_b = point.stress[3];
  EXPECT_NEAR(tau_b, -tau_a, 1e-9 * tau_a) << "the loop is symmetric";
  // Reloading from (−γ_a, −τ_a): τ = τ_b + 2 f((γ − γ_b)/2), and back at γ_a the stress
  // is τ_a again (the model remembers the first reversal).
  const double gamma_b = gamma;
  while (gamma < gamma_a - 0.5 * dg) {
    const double tau = shear(dg);
    worst = std::max(worst, std::abs(tau - (tau_b + 2.0 * f((gamma - gamma_b) / 2.0))));
  }
  EXPECT_LT(worst, 1e-9 * tau_a);
  EXPECT_NEAR(point.stress[3], tau_a, 1e-9 * tau_a);
}

TEST(MultiYield, OneSurfaceIsElasticPerfectlyPlasticVonMises) {
  const Material m = soil(1);
  const double g = shear_modulus(m);
  const double bulk = m.youngs_modulus / (3.0 * (1.0 - 2.0 * m.poisson_ratio));
  Point point(m, isotropic);
  point.start();
  const double q_f = point.state.peak_strength;
  // The reference: a von Mises radial return on the deviator, linear elastic volume.
  Vec4 s = Vec4::Zero();
  double mean = -200e3;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  int plastic = 0;
  for (int k = 0; k < 5000; ++k) {
    const Vec4 d(4e-4 * u(random), 4e-4 * u(random), 0.0, 8e-4 * u(random));
    point.step(d);
    const double v = d[0] + d[1] + d[2];
    const Vec4 de(d[0] - v / 3.0, d[1] - v / 3.0, d[2] - v / 3.0, 0.5 * d[3]);
    s += 2.0 * g * de;
    const double q = multi_yield::von_mises(s);
    if (q > q_f) {
      s *= q_f / q;
      ++plastic;
    }
    mean += bulk * v;
    const Vec4 expected(s[0] + mean, s[1] + mean, s[2] + mean, s[3]);
    worst = std::max(worst, (point.stress - expected).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(plastic, 200) << "the path must load the surface often";
  EXPECT_LT(worst, 1e-6) << "Pa, on stresses of 10⁵ Pa";
}

TEST(MultiYield, AChangeOfConfinementAfterTheSwitchLeavesTheStrength) {
  const Material m = soil(20);
  Point point(m, isotropic);
  point.start();
  const double q_f = point.state.peak_strength;
  // Unload the confinement to tension: a purely volumetric expansion of 3 % (Δεzz too,
  // so that the deviator is not touched).
  for (int k = 0; k < 100; ++k) point.step(Vec4(1e-4, 1e-4, 1e-4, 0.0));
  EXPECT_LT(mean_stress(point.stress), 0.0) << "the point is now in mean tension";
  EXPECT_EQ(point.state.peak_strength, q_f);
  for (int k = 0; k < 4000; ++k) point.step(Vec4(0.0, 0.0, 0.0, 1e-4));
  EXPECT_NEAR(von_mises_stress(point.stress), q_f, 1e-9 * q_f);
  // A second switch (as at the start of an MPM run) keeps the frozen strength.
  point.start();
  EXPECT_EQ(point.state.peak_strength, q_f);
}

TEST(MultiYield, TheSwitchBringsAStressOutsideOntoTheFrozenSurfaceAndLeavesOneInside) {
  const Material m = soil(20);
  // K0 = 0.3 geostatic stress at 20 m depth: outside the frozen surface.
  const double sv = -1700.0 * 9.81 * 20.0;
  Point outside(m, Vec4(0.3 * sv, sv, 0.3 * sv, 0.0));
  const double p0 = mean_stress(outside.stress);
  EXPECT_TRUE(outside.start());
  EXPECT_NEAR(von_mises_stress(outside.stress), outside.state.peak_strength, 1e-9 * p0);
  EXPECT_NEAR(mean_stress(outside.stress), p0, 1e-9 * p0) << "the mean stress is kept";
  // Inside: unchanged, and the surfaces add up to its deviator.
  const Vec4 inside_stress(0.8 * sv, sv, 0.8 * sv, 0.0);
  Point inside(m, inside_stress);
  EXPECT_FALSE(inside.start());
  EXPECT_EQ(inside.stress, inside_stress);
  Vec4 sum = Vec4::Zero();
  for (const Vec4& s : inside.surfaces) sum += s;
  const double mean = (inside_stress[0] + inside_stress[1] + inside_stress[2]) / 3.0;
  const Vec4 deviator(inside_stress[0] - mean, inside_stress[1] - mean, inside_stress[2] - mean,
                      inside_stress[3]);
  EXPECT_LT((sum - deviator).cwiseAbs().maxCoeff(), 1e-9 * std::abs(sv));
  // ... and it sits on the backbone: reloading along the same direction continues it.
  const auto vertices = backbone(m, inside.state.peak_strength);
  EXPECT_GT(von_mises_stress(inside.stress), vertices[1][1]) << "past the first surface";
}

}  // namespace
}  // namespace slide
