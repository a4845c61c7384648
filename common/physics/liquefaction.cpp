#include "common/physics/liquefaction.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/base/error.hpp"

namespace slide::liquefaction {

namespace {

/// √3: γ = √3 εq in simple shear (εq = sqrt(2/3 e:e), e_xy = γ/2).
constexpr double engineering = std::numbers::sqrt3;

}  // namespace

double strength_ratio(ResidualStrengthCorrelation correlation, double n, double given) {
  const double idriss_boulanger = std::exp(n / 16.0 + std::pow((n - 16.0) / 21.2, 3) - 3.0);
  switch (correlation) {
    case ResidualStrengthCorrelation::idriss_boulanger_void_redistribution:
      return idriss_boulanger;
    case ResidualStrengthCorrelation::idriss_boulanger:
      return idriss_boulanger * (1.0 + std::exp(n / 2.4 - 6.6));
    case ResidualStrengthCorrelation::olson_stark:
      return 0.03 + 0.0075 * n;
    case ResidualStrengthCorrelation::ratio:
      return given;
    case ResidualStrengthCorrelation::none:
      break;
  }
  throw Error("liquefaction: correlation \"none\" has no residual strength");
}

UndrainedStrength undrained_strength(const LiquefactionParameters& rule, double sigma_v0) {
  const double cap = std::tan(rule.friction_angle * std::numbers::pi / 180.0);
  const double ratio =
      std::min(strength_ratio(rule.correlation, rule.blow_count, rule.strength_ratio), cap);
  const double confinement = std::max(sigma_v0, 0.0);
  UndrainedStrength s;
  s.residual = std::max(ratio * confinement, rule.minimum_strength);
  s.peak = std::isnan(rule.peak_strength_ratio)
               ? s.residual
               : std::max(std::min(rule.peak_strength_ratio, cap) * confinement, s.residual);
  return s;
}

bool is_liquefied(const LiquefactionParameters& rule, double max_ru, double eps_q) {
  // NaN thresholds compare false: an unused criterion never fires.
  return max_ru >= rule.pore_pressure_ratio || engineering * eps_q >= rule.shear_strain;
}

double cohesion(const Vec4& record, double plastic_shear_strain, double softening_strain) {
  const double peak = record[0], residual = record[1];
  if (!(peak > residual)) return residual;
  const double gamma = engineering * (plastic_shear_strain - record[2]);
  const double left = std::clamp(1.0 - gamma / softening_strain, 0.0, 1.0);
  return residual + (peak - residual) * left;
}

Vec4 make_record(const UndrainedStrength& strength, double plastic_shear_strain, double sigma_v0) {
  return {strength.peak, strength.residual, plastic_shear_strain, sigma_v0};
}

}  // namespace slide::liquefaction
