// Liquefied soil after the transfer (common/physics/liquefaction.hpp): the residual-strength
// correlations at values worked by hand, the cap and the floor, the liquefaction rule,
// the softening, and the residual-strength model in simple shear against its cohesion.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/physics/constitutive.hpp"
#include "common/physics/liquefaction.hpp"

namespace slide {
namespace {

using C = ResidualStrengthCorrelation;

LiquefactionParameters rule_of(C correlation, double blow_count) {
  LiquefactionParameters rule;
  rule.enabled = true;
  rule.correlation = correlation;
  rule.blow_count = blow_count;
  rule.friction_angle = 33.0;
  return rule;
}

// At N = 16 the cubic term of Idriss & Boulanger vanishes: exp(1 − 3) = e⁻²; without void
// redistribution the factor 1 + exp(16/2.4 − 6.6) = 1 + e^(1/15). Olson & Stark's mean
// line at N = 10: 0.03 + 0.075.
TEST(Liquefaction, CorrelationsAtHandWorkedValues) {
  EXPECT_NEAR(liquefaction::strength_ratio(C::idriss_boulanger_void_redistribution, 16.0, 0.0),
              std::exp(-2.0), 1e-15);
  EXPECT_NEAR(liquefaction::strength_ratio(C::idriss_boulanger, 16.0, 0.0),
              std::exp(-2.0) * (1.0 + std::exp(1.0 / 15.0)), 1e-14);
  EXPECT_NEAR(liquefaction::strength_ratio(C::idriss_boulanger_void_redistribution, 0.0, 0.0),
              std::exp(std::pow(-16.0 / 21.2, 3) - 3.0), 1e-15);
  EXPECT_NEAR(liquefaction::strength_ratio(C::olson_stark, 10.0, 0.0), 0.105, 1e-15);
  EXPECT_EQ(liquefaction::strength_ratio(C::ratio, 99.0, 0.12), 0.12);
  EXPECT_THROW((void)liquefaction::strength_ratio(C::none, 10.0, 0.0), Error);
}

// S_r = ratio σ′v0, the ratio capped at tan φ′ (N = 30 gives exp(1.875 + 0.289 − 3) = 0.43
// > tan 20° = 0.364), floored at a minimum, the peak not below the residual.
TEST(Liquefaction, StrengthIsCappedFlooredAndProportionalToSigmaV0) {
  LiquefactionParameters rule = rule_of(C::idriss_boulanger_void_redistribution, 16.0);
  const auto s = liquefaction::undrained_strength(rule, 200e3);
  EXPECT_NEAR(s.residual, std::exp(-2.0) * 200e3, 1e-9);
  EXPECT_EQ(s.peak, s.residual);
  rule.blow_count = 30.0;
  rule.friction_angle = 20.0;
  EXPECT_NEAR(liquefaction::undrained_strength(rule, 100e3).residual,
              std::tan(20.0 * std::numbers::pi / 180.0) * 100e3, 1e-8);
  rule.minimum_strength = 5e3;
  EXPECT_EQ(liquefaction::undrained_strength(rule, 1e3).residual, 5e3);
  EXPECT_EQ(liquefaction::undrained_strength(rule, -4e3).residual, 5e3) << "no negative σ′v0";
  rule.blow_count = 16.0;  // S_r = 13.5 kPa at σ′v0 = 100 kPa
  rule.peak_strength_ratio = 0.3;
  EXPECT_NEAR(liquefaction::undrained_strength(rule, 100e3).peak, 30e3, 1e-9);
  rule.peak_strength_ratio = 0.01;  // a peak below S_r: no softening
  const auto flat = liquefaction::undrained_strength(rule, 100e3);
  EXPECT_EQ(flat.peak, flat.residual);
}

// r_u,max ≥ threshold, or γ = √3 εq ≥ threshold; an unset criterion never fires.
TEST(Liquefaction, RuleByPorePressureRatioOrShearStrain) {
  LiquefactionParameters rule = rule_of(C::olson_stark, 8.0);
  EXPECT_TRUE(liquefaction::is_liquefied(rule, 0.7, 0.0));
  EXPECT_FALSE(liquefaction::is_liquefied(rule, 0.6999, 1.0)) << "no strain criterion given";
  rule.shear_strain = 0.08;
  const double eps_q = 0.08 / std::sqrt(3.0);
  EXPECT_TRUE(liquefaction::is_liquefied(rule, 0.1, eps_q * (1.0 + 1e-12)));
  EXPECT_FALSE(liquefaction::is_liquefied(rule, 0.1, eps_q * (1.0 - 1e-9)));
  rule.pore_pressure_ratio = LiquefactionParameters::unset;
  EXPECT_FALSE(liquefaction::is_liquefied(rule, 5.0, 0.0));
}

// The cohesion falls linearly from the peak at the transfer's εq^p to S_r at γ_s.
TEST(Liquefaction, SofteningIsLinearInTheEngineeringShearStrain) {
  const Vec4 record = liquefaction::make_record({30e3, 10e3}, 0.2, 100e3);
  const double gamma_s = 0.5;
  const double per_gamma = 1.0 / std::sqrt(3.0);  // εq^p of γ = 1
  EXPECT_EQ(liquefaction::cohesion(record, 0.2, gamma_s), 30e3);
  EXPECT_NEAR(liquefaction::cohesion(record, 0.2 + 0.25 * per_gamma, gamma_s), 20e3, 1e-8);
  EXPECT_EQ(liquefaction::cohesion(record, 0.2 + 0.6 * per_gamma, gamma_s), 10e3);
}

Material liquefiable_sand() {
  Material m;
  m.name = "sand";
  m.model = MaterialModel::mohr_coulomb;
  m.density = 2000.0;
  m.youngs_modulus = 100e6;
  m.poisson_ratio = 0.3;
  m.friction_angle = 33.0;
  m.porosity = 0.4;
  m.liquefaction = rule_of(C::ratio, LiquefactionParameters::unset);
  m.liquefaction.strength_ratio = 0.1;
  m.liquefaction.shear_modulus_ratio = 0.2;
  return m;
}

// Simple shear of a liquefied point from an isotropic stress: elastic with G_liq until
// τ = c (Tresca: σ1 − σ3 = 2τ), then τ stays at c; with softening τ follows the
// cohesion of the accumulated plastic strain down to S_r and stays there.
TEST(Liquefaction, ResidualStrengthModelHoldsItsCohesionInSimpleShear) {
  Material m = liquefiable_sand();
  const ConstitutiveModel model = ConstitutiveModel::liquefied(m);
  EXPECT_NEAR(model.shear_modulus(), 0.2 * m.shear_modulus(), 1e-6);
  EXPECT_NEAR(model.lame_lambda() / model.shear_modulus(), 2 * 0.49 / 0.02, 1e-9);
  ASSERT_EQ(model.surfaces(), 1);
  std::vector<Vec4> record{liquefaction::make_record({12e3, 12e3}, 0.0, 120e3)};
  Vec4 stress(-50e3, -50e3, -50e3, 0.0);
  MaterialState state;
  const double step = 1e-5;
  for (int i = 0; i < 2000; ++i) model.update(stress, state, Vec4(0, 0, 0, step), record);
  EXPECT_NEAR(stress[3], 12e3, 1e-6);
  EXPECT_NEAR(stress[0], -50e3, 1e-6) << "the mean stress does not take part";
  // Elastic until τ = c: after γ = c/G_liq the point has yielded, not before.
  MaterialState fresh;
  Vec4 s(-50e3, -50e3, -50e3, 0.0);
  const double gamma_yield = 12e3 / model.shear_modulus();
  EXPECT_FALSE(model.update(s, fresh, Vec4(0, 0, 0, 0.99 * gamma_yield), record));
  EXPECT_TRUE(model.update(s, fresh, Vec4(0, 0, 0, 0.02 * gamma_yield), record));
  // Softening from 30 to 12 kPa over γ_s = 0.3.
  m.liquefaction.peak_strength_ratio = 0.25;
  m.liquefaction.softening_strain = 0.3;
  const ConstitutiveModel softening = ConstitutiveModel::liquefied(m);
  std::vector<Vec4> soft{liquefaction::make_record({30e3, 12e3}, 0.0, 120e3)};
  Vec4 t(-50e3, -50e3, -50e3, 0.0);
  MaterialState st;
  double peak = 0.0;
  for (int i = 0; i < 60000; ++i) {
    softening.update(t, st, Vec4(0, 0, 0, step), soft);
    peak = std::max(peak, t[3]);
  }
  EXPECT_NEAR(peak, 30e3, 30e3 * 2e-3);
  EXPECT_NEAR(t[3], 12e3, 1e-6) << "at γ = 0.6, past γ_s";
  EXPECT_GT(std::sqrt(3.0) * st.plastic_shear_strain, 0.3);
}

}  // namespace
}  // namespace slide
