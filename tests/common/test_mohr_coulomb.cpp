// The constitutive library (common/physics/constitutive.hpp): linear elasticity is exactly
// Hooke's law, the Mohr–Coulomb return puts every stress back on the yield surface by a
// step that obeys the flow rule, a biaxial test fails at the closed-form strength, and
// the invariants and the Jaumann rotation have their textbook values.
//
// The checks use an independent principal decomposition (Eigen's symmetric eigensolver on
// the 3×3 tensor) and the constants Nφ, 2c sqrt(Nφ), c cot φ computed here from φ and c.
#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "common/physics/constitutive.hpp"
#include "tests/support/same_bits.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

constexpr double infinity = std::numeric_limits<double>::infinity();
constexpr double degree = std::numbers::pi / 180.0;

Material soil(double phi, double cohesion, double psi, double tension_cutoff) {
  Material m = synthetic::material("soil", MaterialModel::mohr_coulomb, 1800.0, 50e6, 0.3, phi,
                                   cohesion, psi);
  m.tension_cutoff = tension_cutoff;
  return m;
}

double flow_number(double angle_degrees) {
  const double s = std::sin(angle_degrees * degree);
  return (1.0 + s) / (1.0 - s);
}

/// The constants of the yield surface, computed from the material here.
struct Surface {
  double n_phi;
  double n_psi;
  double k;        // 2c sqrt(Nφ)
  double tension;  // T = min(tension_cutoff, c cot φ)
  double apex;     // c cot φ

  explicit Surface(const Material& m)
      : n_phi(flow_number(m.friction_angle)),
        n_psi(flow_number(m.dilation_angle)),
        k(2.0 * m.cohesion * std::sqrt(n_phi)),
        tension(std::min(m.tension_cutoff, m.apex_stress())),
        apex(m.apex_stress()) {}

  double mohr_coulomb(const Vec3& p) const { return n_phi * p[0] - p[2] - k; }
  double yield(const Vec3& p) const { return std::max(mohr_coulomb(p), p[0] - tension); }
};

Mat3 tensor(const Vec4& s) {
  Mat3 t;
  t << s[0], s[3], 0.0, s[3], s[1], 0.0, 0.0, 0.0, s[2];
  return t;
}

/// Principal stresses σ1 ≥ σ2 ≥ σ3 and their directions (columns), by Eigen's solver.
struct Principal {
  Vec3 values;
  Mat3 directions;
};

Principal principal(const Vec4& s) {
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(tensor(s));
  // Eigen sorts ascending; reverse to σ1 ≥ σ2 ≥ σ3.
  return {solver.eigenvalues().reverse(), solver.eigenvectors().rowwise().reverse()};
}

/// Plane-strain stress with principal values a, b in the plane (major axis at angle
/// theta from x) and z out of plane.
Vec4 stress_from_principal(double a, double b, double z, double theta) {
  const double c = std::cos(theta);
  const double s = std::sin(theta);
  return {a * c * c + b * s * s, a * s * s + b * c * c, z, (a - b) * s * c};
}

// ---------------------------------------------------------------------------------------
// Linear elasticity

TEST(Constitutive, ElasticIncrementIsHookesLaw) {
  const Material m = soil(30.0, 1e4, 0.0, infinity);
  const double e = m.youngs_modulus;
  const double nu = m.poisson_ratio;
  // D in the E–ν form, independent of the Lamé constants the model uses.
  const double c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
  const double g = e / (2.0 * (1.0 + nu));
  const ConstitutiveModel model = ConstitutiveModel::elastic(m);
  EXPECT_EQ(model.model(), MaterialModel::linear_elastic);
  EXPECT_NEAR(model.shear_modulus(), g, 1e-12 * g);
  EXPECT_NEAR(model.lame_lambda(), e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), 1e-12 * g);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> strain(-1e-3, 1e-3);
  for (int n = 0; n < 100; ++n) {
    const Vec4 de{strain(random), strain(random), n % 2 == 0 ? 0.0 : strain(random),
                  strain(random)};
    const Vec4 expected{c * ((1.0 - nu) * de[0] + nu * (de[1] + de[2])),
                        c * ((1.0 - nu) * de[1] + nu * (de[0] + de[2])),
                        c * ((1.0 - nu) * de[2] + nu * (de[0] + de[1])), g * de[3]};
    const double scale = expected.cwiseAbs().maxCoeff();
    const Vec4 ds = model.elastic_stress_increment(de);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(ds[i], expected[i], 1e-12 * scale);

    // The elastic model's update adds exactly that and never yields, whatever the stress.
    Vec4 stress{1e9, -3e9, 2e9, 5e8};
    const Vec4 before = stress;
    MaterialState state;
    EXPECT_FALSE(model.update(stress, state, de));
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(stress[i] - before[i], expected[i], 1e-6 * scale);
    EXPECT_EQ(state.plastic_shear_strain, 0.0);
    EXPECT_EQ(model.yield_function(stress), -infinity);
  }
}

TEST(MohrCoulomb, BelowYieldIsHookesLaw) {
  const Material m = soil(30.0, 1e4, 5.0, infinity);
  const ConstitutiveModel model = ConstitutiveModel::from(m);
  const ConstitutiveModel elastic = ConstitutiveModel::elastic(m);
  ASSERT_EQ(model.model(), MaterialModel::mohr_coulomb);
  const Vec4 confined{-200e3, -250e3, -220e3, 10e3};  // far inside the surface
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> strain(-1e-4, 1e-4);
  for (int n = 0; n < 100; ++n) {
    const Vec4 de{strain(random), strain(random), 0.0, strain(random)};
    Vec4 stress = confined;
    MaterialState state;
    EXPECT_FALSE(model.update(stress, state, de));
    const Vec4 expected = confined + elastic.elastic_stress_increment(de);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(stress[i], expected[i], 1e-12 * 250e3);
    EXPECT_LT(model.yield_function(stress), 0.0);
    EXPECT_EQ(state.plastic_shear_strain, 0.0);
    EXPECT_EQ(state.plastic_volumetric_strain, 0.0);
  }
}

TEST(MohrCoulomb, ZeroIncrementOnAdmissibleStressIsNoOp) {
  const ConstitutiveModel model = ConstitutiveModel::from(soil(25.0, 5e3, 5.0, 2e3));
  const Vec4 zero = Vec4::Zero();
  const std::array<Vec4, 3> admissible{Vec4{-100e3, -150e3, -120e3, 20e3}, Vec4{0.0, 0.0, 0.0, 0.0},
                                       Vec4{1e3, -5e3, -2e3, 1e3}};
  for (const Vec4& s : admissible) {
    ASSERT_LE(model.yield_function(s), 0.0);
    Vec4 stress = s;
    MaterialState state{0.25, -0.125};
    EXPECT_FALSE(model.update(stress, state, zero));
    EXPECT_EQ(stress, s);
    EXPECT_EQ(state.plastic_shear_strain, 0.25);
    EXPECT_EQ(state.plastic_volumetric_strain, -0.125);
  }
  // A stress the return left on the surface is admissible: a second call does nothing.
  Vec4 stress{-50e3, -400e3, -100e3, 30e3};
  MaterialState state;
  ASSERT_TRUE(model.update(stress, state, zero));
  const Vec4 returned = stress;
  const MaterialState after = state;
  EXPECT_FALSE(model.update(stress, state, zero));
  EXPECT_EQ(stress, returned);
  EXPECT_EQ(state.plastic_shear_strain, after.plastic_shear_strain);
}

// ---------------------------------------------------------------------------------------
// Plane-strain biaxial compression: σxx held at −σc by mixed control, εyy compressed.
// Peak (and residual, perfect plasticity) |σyy| = σc Nφ + 2c sqrt(Nφ); afterwards the
// plastic strain ratio Δεxx/|Δεyy| = Nψ.

struct BiaxialCase {
  double phi, cohesion, psi, confining;
};

TEST(MohrCoulomb, BiaxialCompressionFailsAtClosedFormStrength) {
  const std::array<BiaxialCase, 4> cases{
      BiaxialCase{30.0, 10e3, 0.0, 100e3}, BiaxialCase{30.0, 10e3, 10.0, 100e3},
      BiaxialCase{22.2, 1e3, 0.0, 50e3}, BiaxialCase{40.0, 0.0, 20.0, 300e3}};
  for (const BiaxialCase& test : cases) {
    SCOPED_TRACE(::testing::Message() << "phi " << test.phi << " c " << test.cohesion << " psi "
                                      << test.psi << " sigma_c " << test.confining);
    const Material m = soil(test.phi, test.cohesion, test.psi, infinity);
    const Surface surface(m);
    const ConstitutiveModel model = ConstitutiveModel::from(m);
    const double strength = test.confining * surface.n_phi + surface.k;  // |σyy| at failure

    Vec4 stress = Vec4::Constant(-test.confining);
    stress[3] = 0.0;
    MaterialState state;
    const int steps = 400;
    const double deyy = -0.05 / steps;  // 5 % axial strain, well past failure
    const double lambda = model.lame_lambda();
    const double m_modulus = lambda + 2.0 * model.shear_modulus();
    double peak = 0.0;
    int plastic_steps = 0;
    for (int step = 0; step < steps; ++step) {
      // Mixed control: find Δεxx with σxx = −σc after the full update. The update is
      // piecewise linear in Δεxx, so the secant iteration ends in a few steps.
      auto residual = [&](double dexx, Vec4& s, MaterialState& st) {
        s = stress;
        st = state;
        const bool yielded = model.update(s, st, Vec4{dexx, deyy, 0.0, 0.0});
        return std::pair{s[0] + test.confining, yielded};
      };
      Vec4 s;
      MaterialState st;
      double x0 = -lambda / m_modulus * deyy;  // the elastic answer
      double r0 = residual(x0, s, st).first;
      double x1 = x0 + 1e-3 * std::abs(deyy);
      double r1 = residual(x1, s, st).first;
      for (int iteration = 0; iteration < 50 && std::abs(r1) > 1e-12 * test.confining;
           ++iteration) {
        const double x2 = x1 - r1 * (x1 - x0) / (r1 - r0);
        x0 = x1;
        r0 = r1;
        x1 = x2;
        r1 = residual(x1, s, st).first;
      }
      ASSERT_LE(std::abs(r1), 1e-10 * test.confining) << "mixed control did not converge";
      const bool yielded = residual(x1, s, st).second;
      stress = s;
      state = st;
      peak = std::max(peak, -stress[1]);
      const Principal p = principal(stress);
      const double scale = strength;
      EXPECT_LE(surface.yield(p.values), 1e-9 * scale);
      if (yielded) {
        // On the surface, at the closed-form strength, σzz between the other two.
        EXPECT_NEAR(surface.yield(p.values), 0.0, 1e-9 * scale);
        EXPECT_NEAR(-stress[1], strength, 1e-8 * strength);
        EXPECT_LT(stress[1], stress[2]);
        EXPECT_LT(stress[2], stress[0]);
        if (plastic_steps > 0) {  // steady state: all of the increment is plastic
          EXPECT_NEAR(x1 / -deyy, surface.n_psi, 1e-8 * surface.n_psi);
        }
        ++plastic_steps;
      } else {
        EXPECT_EQ(plastic_steps, 0) << "unloading should not happen on this path";
      }
    }
    EXPECT_GT(plastic_steps, steps / 2);
    EXPECT_NEAR(peak, strength, 1e-8 * strength);
    EXPECT_GT(state.plastic_shear_strain, 0.0);
    if (test.psi == 0.0) {
      EXPECT_NEAR(state.plastic_volumetric_strain, 0.0, 1e-15);
    } else {
      EXPECT_GT(state.plastic_volumetric_strain, 0.0);
    }
  }
}

// ---------------------------------------------------------------------------------------
// The return map on random trial stresses.

/// Where a returned stress sits, from its principal values (an independent reading of
/// the geometry, not the algorithm's own bookkeeping).
enum class Region {
  plane,
  edge_compression,  // σ1 = σ2 on the Mohr–Coulomb surface
  edge_extension,    // σ2 = σ3 on the Mohr–Coulomb surface
  apex,
  tension_plane,
  tension_edge,          // σ1 = σ2 = T
  tension_mohr_coulomb,  // σ1 = T and f = 0
  corner_two_tension,    // (T, T, Nφ T − 2c sqrt(Nφ))
  corner_one_tension,    // (T, Nφ T − 2c sqrt(Nφ), twice)
  corner_three_tension,  // (T, T, T)
  off_surface,
};

const char* name(Region r) {
  switch (r) {
    case Region::plane:
      return "plane";
    case Region::edge_compression:
      return "edge s1=s2";
    case Region::edge_extension:
      return "edge s2=s3";
    case Region::apex:
      return "apex";
    case Region::tension_plane:
      return "tension plane";
    case Region::tension_edge:
      return "tension edge s1=s2=T";
    case Region::tension_mohr_coulomb:
      return "edge s1=T, f=0";
    case Region::corner_two_tension:
      return "corner (T,T,s)";
    case Region::corner_one_tension:
      return "corner (T,s,s)";
    case Region::corner_three_tension:
      return "corner (T,T,T)";
    case Region::off_surface:
      return "off the surface";
  }
  return "?";
}

Region classify(const Surface& surface, const Vec3& p, double tolerance) {
  const bool on_mc = std::abs(surface.mohr_coulomb(p)) <= tolerance;
  const bool on_t = surface.tension < surface.apex && std::abs(p[0] - surface.tension) <= tolerance;
  const bool equal_12 = p[0] - p[1] <= tolerance;
  const bool equal_23 = p[1] - p[2] <= tolerance;
  if (on_t) {
    if (equal_12 && equal_23) return Region::corner_three_tension;
    if (on_mc && equal_12) return Region::corner_two_tension;
    if (on_mc && equal_23) return Region::corner_one_tension;
    if (on_mc) return Region::tension_mohr_coulomb;
    if (equal_12) return Region::tension_edge;
    return Region::tension_plane;
  }
  if (!on_mc) return Region::off_surface;
  if (equal_12 && equal_23) return Region::apex;
  if (equal_12) return Region::edge_compression;
  if (equal_23) return Region::edge_extension;
  return Region::plane;
}

/// Checks that Δεᵖ (principal, in the trial's σ1, σ2, σ3 slots) is a non-negative
/// combination of the plastic-potential gradients of the planes active in `region`.
void expect_flow_rule(Region region, const Surface& surface, const Vec3& e, double tolerance) {
  const double n = surface.n_psi;
  switch (region) {
    case Region::plane:  // Δλ (Nψ, 0, −1)
      EXPECT_NEAR(e[1], 0.0, tolerance);
      EXPECT_NEAR(e[0], -n * e[2], tolerance);
      EXPECT_GE(-e[2], -tolerance);
      break;
    case Region::edge_compression:  // Δλa (Nψ, 0, −1) + Δλb (0, Nψ, −1)
      EXPECT_NEAR(e[2], -(e[0] + e[1]) / n, tolerance);
      EXPECT_GE(e[0], -tolerance);
      EXPECT_GE(e[1], -tolerance);
      break;
    case Region::edge_extension:  // Δλa (Nψ, 0, −1) + Δλb (Nψ, −1, 0)
      EXPECT_NEAR(e[0], -n * (e[1] + e[2]), tolerance);
      EXPECT_GE(-e[1], -tolerance);
      EXPECT_GE(-e[2], -tolerance);
      break;
    case Region::tension_plane:  // Δλ (1, 0, 0)
      EXPECT_NEAR(e[1], 0.0, tolerance);
      EXPECT_NEAR(e[2], 0.0, tolerance);
      EXPECT_GE(e[0], -tolerance);
      break;
    case Region::tension_edge:  // Δλa (1, 0, 0) + Δλb (0, 1, 0)
      EXPECT_NEAR(e[2], 0.0, tolerance);
      EXPECT_GE(e[0], -tolerance);
      EXPECT_GE(e[1], -tolerance);
      break;
    case Region::tension_mohr_coulomb:  // Δλa (Nψ, 0, −1) + Δλb (1, 0, 0)
      EXPECT_NEAR(e[1], 0.0, tolerance);
      EXPECT_GE(-e[2], -tolerance);
      EXPECT_GE(e[0] + n * e[2], -tolerance);
      break;
    case Region::corner_three_tension:  // the three unit vectors
      EXPECT_GE(e.minCoeff(), -tolerance);
      break;
    case Region::corner_one_tension:  // (Nψ, 0, −1), (Nψ, −1, 0), (1, 0, 0)
      EXPECT_GE(-e[1], -tolerance);
      EXPECT_GE(-e[2], -tolerance);
      EXPECT_GE(e[0] + n * (e[1] + e[2]), -tolerance);
      break;
    case Region::corner_two_tension:  // (Nψ, 0, −1), (0, Nψ, −1), (1, 0, 0), (0, 1, 0)
      EXPECT_GE(-e[2], -tolerance);
      EXPECT_GE(e[0], -tolerance);
      EXPECT_GE(e[1], -tolerance);
      EXPECT_GE(e[0] + e[1] + n * e[2], -tolerance);
      break;
    case Region::apex:  // tension beyond the apex is relieved by dilation
      EXPECT_GT(e.sum(), 0.0);
      break;
    case Region::off_surface:
      break;
  }
}

/// Returns 10⁴ random trial stresses (principal values drawn from [−compression, tension],
/// random in-plane direction, fixed seed) and checks each return; every region in
/// `expected` must be reached at least once.
void check_random_returns(const std::string& label, const Material& material, double compression,
                          double tension, const std::vector<Region>& expected) {
  SCOPED_TRACE(label);
  const Surface surface(material);
  const ConstitutiveModel model = ConstitutiveModel::from(material);
  const double g = model.shear_modulus();
  const double lambda = model.lame_lambda();
  std::mt19937_64 random(20240601);
  std::uniform_real_distribution<double> value(-compression, tension);
  std::uniform_real_distribution<double> angle(0.0, std::numbers::pi);
  std::map<Region, int> counts;
  int outside = 0;
  for (int n = 0; n < 10000; ++n) {
    const Vec4 trial =
        stress_from_principal(value(random), value(random), value(random), angle(random));
    const Principal pt = principal(trial);
    const double scale = pt.values.cwiseAbs().maxCoeff() + material.cohesion;
    Vec4 stress = trial;
    MaterialState state;
    const bool yielded = model.update(stress, state, Vec4::Zero());
    const bool was_outside = surface.yield(pt.values) > 1e-12 * scale;
    ASSERT_EQ(yielded, was_outside) << "trial " << trial.transpose();
    if (!yielded) {
      EXPECT_EQ(stress, trial);
      continue;
    }
    ++outside;

    // On the surface: the largest yield function is zero (not below: the return is not
    // to the inside), and the model's own yield function agrees.
    const Principal pr = principal(stress);
    EXPECT_NEAR(surface.yield(pr.values), 0.0, 1e-9 * scale) << "trial " << trial.transpose();
    EXPECT_NEAR(model.yield_function(stress), 0.0, 1e-9 * scale);

    // Same principal directions: the returned tensor is diagonal in the trial's basis.
    const Mat3 rotated = pt.directions.transpose() * tensor(stress) * pt.directions;
    EXPECT_NEAR(rotated(0, 1), 0.0, 1e-9 * scale);
    EXPECT_NEAR(rotated(0, 2), 0.0, 1e-9 * scale);
    EXPECT_NEAR(rotated(1, 2), 0.0, 1e-9 * scale);

    // Flow rule: Δεᵖ = D⁻¹(σ_trial − σ) in the trial's principal slots.
    const Vec3 ds = pt.values - rotated.diagonal();
    const Vec3 plastic =
        (ds - lambda / (3.0 * lambda + 2.0 * g) * ds.sum() * Vec3::Ones()) / (2.0 * g);
    const Region region = classify(surface, pr.values, 1e-9 * scale);
    ASSERT_NE(region, Region::off_surface) << "trial " << trial.transpose();
    ++counts[region];
    expect_flow_rule(region, surface, plastic, 1e-9 * scale / g);

    // The state takes the same plastic strain: tr Δεᵖ and sqrt(2/3 Δeᵖ:Δeᵖ).
    const Vec3 deviatoric = plastic - plastic.sum() / 3.0 * Vec3::Ones();
    EXPECT_NEAR(state.plastic_volumetric_strain, plastic.sum(), 1e-9 * scale / g);
    EXPECT_NEAR(state.plastic_shear_strain, std::sqrt(2.0 / 3.0 * deviatoric.squaredNorm()),
                1e-9 * scale / g);

    // Tension cut-off: no principal stress above T.
    EXPECT_LE(pr.values[0], surface.tension + 1e-9 * scale);

    // ψ = 0: returns to the plane and to the edges are isochoric. The tension and apex
    // returns cannot be: they relieve a mean tension, so they always dilate.
    const bool shear_return = region == Region::plane || region == Region::edge_compression ||
                              region == Region::edge_extension;
    if (material.dilation_angle == 0.0 && shear_return) {
      EXPECT_NEAR(state.plastic_volumetric_strain, 0.0, 1e-12 * state.plastic_shear_strain);
    }
    if (!shear_return) {
      EXPECT_GT(state.plastic_volumetric_strain, 0.0);
    }
  }
  std::string summary = label + ": " + std::to_string(outside) + " returns;";
  for (const auto& [region, count] : counts) {
    summary += std::string(" ") + name(region) + " " + std::to_string(count) + ",";
  }
  std::cout << summary << "\n";
  for (Region region : expected) {
    EXPECT_GT(counts[region], 0) << "no return to " << name(region);
  }
}

TEST(MohrCoulomb, RandomTrialsReturnOntoTheSurfaceWithTheApex) {
  // T at the apex (tension_cutoff above it): plane, both edges and the apex.
  const Material m = soil(30.0, 10e3, 10.0, infinity);
  check_random_returns(
      "phi 30, psi 10, no cut-off", m, 300e3, 100e3,
      {Region::plane, Region::edge_compression, Region::edge_extension, Region::apex});
  const Material associated = soil(30.0, 10e3, 30.0, infinity);
  check_random_returns(
      "phi 30, psi 30, no cut-off", associated, 300e3, 100e3,
      {Region::plane, Region::edge_compression, Region::edge_extension, Region::apex});
}

TEST(MohrCoulomb, RandomTrialsReturnOntoTheSurfaceWithTensionCutoff) {
  // T = 5 kPa below the apex c cot φ = 17.3 kPa: every tension region appears too.
  const Material m = soil(30.0, 10e3, 0.0, 5e3);
  check_random_returns(
      "phi 30, psi 0, T 5 kPa", m, 150e3, 40e3,
      {Region::plane, Region::edge_compression, Region::edge_extension, Region::tension_plane,
       Region::tension_edge, Region::tension_mohr_coulomb, Region::corner_two_tension,
       Region::corner_one_tension, Region::corner_three_tension});
  // A no-tension material (T = 0, taken literally) with dilation.
  const Material no_tension = soil(35.0, 20e3, 15.0, 0.0);
  check_random_returns(
      "phi 35, psi 15, T 0", no_tension, 200e3, 40e3,
      {Region::plane, Region::edge_compression, Region::edge_extension, Region::tension_plane,
       Region::tension_edge, Region::tension_mohr_coulomb, Region::corner_two_tension,
       Region::corner_one_tension, Region::corner_three_tension});
}

TEST(MohrCoulomb, RandomTrialsTrescaWithAndWithoutCutoff) {
  // φ = 0 has no apex: without a cut-off only the plane and the edges remain.
  const Material tresca = soil(0.0, 20e3, 0.0, infinity);
  check_random_returns("Tresca", tresca, 200e3, 200e3,
                       {Region::plane, Region::edge_compression, Region::edge_extension});
  const Material tresca_cutoff = soil(0.0, 20e3, 0.0, 10e3);
  check_random_returns(
      "Tresca, T 10 kPa", tresca_cutoff, 200e3, 100e3,
      {Region::plane, Region::edge_compression, Region::edge_extension, Region::tension_plane,
       Region::tension_edge, Region::tension_mohr_coulomb, Region::corner_two_tension,
       Region::corner_one_tension, Region::corner_three_tension});
}

TEST(MohrCoulomb, TrialsWithEqualPrincipalStressesReturnOntoTheSurface) {
  // Ties (σ1 = σ2, σ2 = σ3, hydrostatic, in-plane isotropic) sit on the boundaries between
  // return regions; the result must still be admissible and on the surface.
  std::mt19937_64 random(5);
  std::uniform_int_distribution<int> level(-6, 3);
  std::uniform_int_distribution<int> eighth(0, 3);
  for (double phi : {0.0, 30.0}) {
    for (double cutoff : {0.0, 2e3, infinity}) {
      const Material m = soil(phi, 5e3, phi / 2.0, cutoff);
      const Surface surface(m);
      const ConstitutiveModel model = ConstitutiveModel::from(m);
      for (int n = 0; n < 2000; ++n) {
        const double step = 5e3;
        const Vec4 trial =
            stress_from_principal(level(random) * step, level(random) * step, level(random) * step,
                                  eighth(random) * std::numbers::pi / 4.0);
        const double scale = 6.0 * step + m.cohesion;
        Vec4 stress = trial;
        MaterialState state;
        const bool yielded = model.update(stress, state, Vec4::Zero());
        const double f = surface.yield(principal(stress).values);
        EXPECT_LE(f, 1e-9 * scale) << "trial " << trial.transpose();
        if (yielded) {
          EXPECT_NEAR(f, 0.0, 1e-9 * scale) << "trial " << trial.transpose();
        }
        EXPECT_TRUE(std::isfinite(state.plastic_shear_strain));
        EXPECT_TRUE(std::isfinite(state.plastic_volumetric_strain));
      }
    }
  }
}

// ---------------------------------------------------------------------------------------
// Tension cut-off semantics: T = min(tension_cutoff, c cot φ), taken literally.

TEST(MohrCoulomb, TensionCutoffIsRespected) {
  const Material m = soil(30.0, 10e3, 0.0, 5e3);
  const ConstitutiveModel model = ConstitutiveModel::from(m);
  ASSERT_LT(5e3, m.apex_stress());
  // Uniaxial-strain extension in x from a stress-free state: σxx stops at T.
  Vec4 stress = Vec4::Zero();
  MaterialState state;
  bool yielded = false;
  for (int step = 0; step < 100; ++step) {
    yielded = model.update(stress, state, Vec4{1e-5, 0.0, 0.0, 0.0}) || yielded;
    EXPECT_LE(principal(stress).values[0], 5e3 * (1.0 + 1e-12));
  }
  EXPECT_TRUE(yielded);
  EXPECT_NEAR(stress[0], 5e3, 1e-9 * 5e3);
  EXPECT_GT(state.plastic_volumetric_strain, 0.0);

  // T = 0: no tension at all.
  const ConstitutiveModel no_tension = ConstitutiveModel::from(soil(30.0, 10e3, 0.0, 0.0));
  Vec4 pulled{30e3, -5e3, 1e3, 4e3};
  EXPECT_TRUE(no_tension.update(pulled, state, Vec4::Zero()));
  EXPECT_LE(principal(pulled).values[0], 1e-9 * 30e3);

  // A cut-off above the apex (or +∞) leaves the pyramid: the apex is the admissible limit.
  for (double cutoff : {m.apex_stress(), 2.0 * m.apex_stress(), infinity}) {
    const ConstitutiveModel pyramid = ConstitutiveModel::from(soil(30.0, 10e3, 0.0, cutoff));
    const double apex = m.apex_stress();
    EXPECT_NEAR(pyramid.yield_function(Vec4{apex, apex, apex, 0.0}), 0.0, 1e-9 * apex);
    Vec4 hydrostatic{3.0 * apex, 3.0 * apex, 3.0 * apex, 0.0};
    EXPECT_TRUE(pyramid.update(hydrostatic, state, Vec4::Zero()));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(hydrostatic[i], apex, 1e-9 * apex);
    EXPECT_NEAR(hydrostatic[3], 0.0, 1e-9 * apex);
  }
}

// ---------------------------------------------------------------------------------------
// The switch from the elastic geostatic state (docs/method.md §3): K0 = ν/(1−ν) is below the
// active limit, so deep points return, here to the edge σxx = σzz (= σ1 = σ2).

TEST(MohrCoulomb, GeostaticK0StateReturnsToTheCompressionEdge) {
  Material m = soil(22.2, 1e3, 0.0, 0.0);
  m.youngs_modulus = 23.8e6;
  m.poisson_ratio = 0.23;
  m.density = 1700.0;
  m.tension_cutoff = m.apex_stress();  // what the case reader fills in by default
  const Surface surface(m);
  const ConstitutiveModel model = ConstitutiveModel::from(m);
  std::vector<Vec4> stress;
  for (double depth = 0.5; depth < 40.0; depth += 1.0) {
    const double syy = -m.density * gravity_acceleration * depth;
    stress.push_back({m.k0() * syy, syy, m.k0() * syy, 0.0});
  }
  std::vector<MaterialState> state(stress.size());
  const std::vector<Vec4> zero(stress.size(), Vec4::Zero());
  std::vector<std::uint8_t> yielded(stress.size(), 7);
  const std::size_t count = update_stresses(model, stress, state, zero, yielded);
  std::size_t flagged = 0;
  for (std::size_t i = 0; i < stress.size(); ++i) {
    flagged += yielded[i];
    const Vec3 p = principal(stress[i]).values;
    const double scale = std::abs(p[2]) + m.cohesion;
    EXPECT_LE(surface.yield(p), 1e-9 * scale);
    if (yielded[i] == 0) continue;
    EXPECT_NEAR(surface.yield(p), 0.0, 1e-9 * scale);
    EXPECT_NEAR(stress[i][0], stress[i][2], 1e-9 * scale);  // still σxx = σzz
    EXPECT_EQ(stress[i][3], 0.0);
    EXPECT_NEAR(state[i].plastic_volumetric_strain, 0.0, 1e-18);  // ψ = 0
  }
  EXPECT_EQ(count, flagged);
  EXPECT_GT(count, stress.size() / 2);  // all but the shallowest points (cohesion)

  // Wrong sizes are a programming error reported as such.
  std::vector<Vec4> short_increment(stress.size() - 1, Vec4::Zero());
  EXPECT_THROW(update_stresses(model, stress, state, short_increment), std::exception);

  // The elastic model never yields and leaves the flags at zero.
  const ConstitutiveModel elastic = ConstitutiveModel::elastic(m);
  EXPECT_EQ(update_stresses(elastic, stress, state, zero, yielded), 0u);
  for (std::uint8_t flag : yielded) EXPECT_EQ(flag, 0);
}

// ---------------------------------------------------------------------------------------
// Jaumann rotation and invariants.

/// Equal bits, or where products are fused into FMAs within a few ulps of `scale`.
void expect_same(double from_pair, double from_scalar, double scale) {
  testing::expect_same_bits(from_pair, from_scalar, 4e-15 * scale);
}

// advance_mohr_coulomb_pair, the MPM kernels' two particles and the FE kernels' two
// one-point elements at once, against two calls of advance_point, objective or not: the same
// stresses, states, strains and yield flags, for random velocity gradients and random stresses,
// half of them first brought onto the surface so that elastic steps and returns both occur, in
// either lane.
TEST(MohrCoulomb, TwoPointsAtOnceGiveTheBitsOfOneAtATime) {
  const Material material = soil(30.0, 10e3, 5.0, 5e3);
  const ConstitutiveModel model = ConstitutiveModel::from(material);
  std::mt19937_64 random(31);
  std::uniform_real_distribution<double> value(-150e3, 20e3);
  std::uniform_real_distribution<double> angle(0.0, std::numbers::pi);
  std::uniform_real_distribution<double> rate(-0.02, 0.02);
  const double dt = 0.01;
  int yielded_points = 0, elastic_points = 0;
  for (int n = 0; n < 5000; ++n) {
    const bool objective = n % 3 != 0;  // MPM and updated-Lagrangian FE; small-strain FE
    std::array<Vec4, 2> stress, strain, gradient;
    std::array<MaterialState, 2> state;
    for (std::size_t i = 0; i < 2; ++i) {
      stress[i] = stress_from_principal(value(random), value(random), value(random), angle(random));
      // The same admissible start for about half the points: elastic steps too.
      if (n % 2 == 0) model.start(stress[i], state[i]);
      gradient[i] = Vec4(rate(random), rate(random), rate(random), rate(random));
      strain[i] = Vec4(rate(random), rate(random), 0.0, rate(random));
      state[i].plastic_shear_strain = 0.01 * static_cast<double>(i + 1);
    }
    auto scalar_stress = stress, scalar_strain = strain;
    auto scalar_state = state;
    std::array<bool, 2> scalar_yielded{};
    for (std::size_t i = 0; i < 2; ++i) {
      scalar_yielded[i] = advance_point(model, gradient[i], dt, objective, scalar_stress[i],
                                        scalar_state[i], {}, scalar_strain[i]);
    }
    const std::array<bool, 2> yielded =
        advance_mohr_coulomb_pair(model, dt, objective,
                                  {{{gradient[0], &stress[0], &state[0], &strain[0]},
                                    {gradient[1], &stress[1], &state[1], &strain[1]}}});
    for (std::size_t i = 0; i < 2; ++i) {
      SCOPED_TRACE(::testing::Message() << "pair " << n << ", point " << i);
      ASSERT_EQ(yielded[i], scalar_yielded[i]);
      (yielded[i] ? yielded_points : elastic_points) += 1;
      const double scale = scalar_stress[i].cwiseAbs().maxCoeff() + material.cohesion;
      for (int c = 0; c < 4; ++c) {
        expect_same(stress[i][c], scalar_stress[i][c], scale);
        expect_same(strain[i][c], scalar_strain[i][c], 1.0);
      }
      expect_same(state[i].plastic_shear_strain, scalar_state[i].plastic_shear_strain, 1.0);
      expect_same(state[i].plastic_volumetric_strain, scalar_state[i].plastic_volumetric_strain,
                  1.0);
    }
  }
  EXPECT_GT(yielded_points, 2000);
  EXPECT_GT(elastic_points, 1000);
}

TEST(Constitutive, JaumannRotationOfHydrostaticStressIsZero) {
  Vec4 stress{-3e5, -3e5, -3e5, 0.0};
  const Vec4 before = stress;
  rotate_jaumann(stress, 0.07);
  EXPECT_EQ(stress, before);
}

TEST(Constitutive, JaumannRotationOfUniaxialStressMatchesTheRotationFormula) {
  // ω = ½(∂vx/∂y − ∂vy/∂x)Δt is minus the rigid rotation angle θ (counter-clockwise).
  const double s = -2e5;
  for (double omega : {1e-3, -4e-4, 1e-5}) {
    Vec4 stress{s, 0.0, 0.4 * s, 0.0};
    rotate_jaumann(stress, omega);
    EXPECT_EQ(stress[0], s);
    EXPECT_EQ(stress[1], 0.0);
    EXPECT_EQ(stress[2], 0.4 * s);  // the z axis does not rotate
    EXPECT_DOUBLE_EQ(stress[3], -omega * s);
    // First-order agreement with R σ Rᵀ, R the rotation by θ = −ω.
    const Vec4 exact = stress_from_principal(s, 0.0, 0.4 * s, -omega);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(stress[i], exact[i], 2.0 * omega * omega * std::abs(s));
  }
  // A general stress: Δσxx = 2ωσxy, Δσyy = −2ωσxy, Δσxy = ω(σyy − σxx).
  Vec4 general{-1e5, -3e5, -2e5, 4e4};
  rotate_jaumann(general, 0.01);
  EXPECT_DOUBLE_EQ(general[0], -1e5 + 2.0 * 0.01 * 4e4);
  EXPECT_DOUBLE_EQ(general[1], -3e5 - 2.0 * 0.01 * 4e4);
  EXPECT_DOUBLE_EQ(general[3], 4e4 + 0.01 * (-3e5 + 1e5));
}

TEST(Constitutive, StressAndStrainInvariants) {
  EXPECT_DOUBLE_EQ(mean_stress(Vec4{-1e5, -2e5, -3e5, 7e4}), 2e5);
  EXPECT_NEAR(von_mises_stress(Vec4{-1e5, -1e5, -1e5, 0.0}), 0.0, 1e-9);
  EXPECT_NEAR(von_mises_stress(Vec4{-6e5, 0.0, 0.0, 0.0}), 6e5, 1e-9);  // uniaxial: q = |σ|
  // Pure shear τ: q = sqrt(3) τ.
  EXPECT_NEAR(von_mises_stress(Vec4{0.0, 0.0, 0.0, 5e4}), std::sqrt(3.0) * 5e4, 1e-9);
  // Pure shear strain γxy: εq = |γ|/sqrt(3) (εxy = γ/2 counts twice in e:e).
  for (double gamma : {0.03, -0.2}) {
    EXPECT_NEAR(deviatoric_strain(Vec4{0.0, 0.0, 0.0, gamma}), std::abs(gamma) / std::sqrt(3.0),
                1e-15);
  }
  // Isotropic strain has no deviator; uniaxial strain ε gives εq = 2|ε|/3.
  EXPECT_NEAR(deviatoric_strain(Vec4{0.01, 0.01, 0.01, 0.0}), 0.0, 1e-15);
  EXPECT_NEAR(deviatoric_strain(Vec4{0.0, -0.03, 0.0, 0.0}), 0.02, 1e-15);
}

}  // namespace
}  // namespace slide
