// Liquefied soil after the transfer (docs/method.md §10): which particles count as
// liquefied, and the undrained residual strength they have in MPM.
//
// A particle of a material with a liquefaction rule is liquefied when the largest
// pore-pressure ratio its source Gauss point reached in the FE phase, r_u,max, is at
// least the rule's threshold (default 0.7), or when its engineering shear strain
// γ = √3 εq (the simple-shear γ of the deviatoric invariant) is at least the rule's.
// It then carries an undrained strength that does not depend on its confinement:
// φ = 0, c = S_r, with the ratio S_r/σ′v0 of a field correlation of the blow count
// N = (N1)60cs-Sr and the vertical effective stress σ′v0 before the shaking:
//
//   Idriss & Boulanger (2008, SPT-based, void redistribution significant):
//       S_r/σ′v0 = exp(N/16 + ((N − 16)/21.2)³ − 3)
//   Idriss & Boulanger (2008, void redistribution negligible):
//       S_r/σ′v0 = exp(N/16 + ((N − 16)/21.2)³ − 3) · (1 + exp(N/2.4 − 6.6))
//   Olson & Stark (2002): S_r/σ′v0 = 0.03 + 0.0075 N  (their mean line, (N1)60 ≤ 12)
//   ratio: a given S_r/σ′v0.
//
// The ratio is capped at tan φ′ (the drained strength of a normally consolidated soil),
// S_r is floored at a given minimum, and, optionally, the strength softens linearly from
// a peak S_u,peak = (peak ratio) σ′v0 to S_r over an engineering plastic shear strain γ_s
// (counted from the transfer). The liquefied soil's shear modulus is a fraction of its
// material's, with an undrained Poisson's ratio close to ½.
#pragma once

#include <span>

#include "common/base/types.hpp"
#include "common/physics/material.hpp"

namespace slide::liquefaction {

/// S_r/σ′v0 of a correlation at the blow count N (correlation `ratio`: `given`), uncapped.
double strength_ratio(ResidualStrengthCorrelation correlation, double blow_count, double given);

/// The per-point record of a liquefied particle (its model's one state record):
/// [S_u,peak, S_r, εq^p at the transfer, σ′v0], Pa, –, Pa.
struct UndrainedStrength {
  double peak = 0.0;      ///< where the softening starts (= residual without softening), Pa
  double residual = 0.0;  ///< S_r, Pa
};

/// A material's undrained strengths at a point whose σ′v0 (compression positive, Pa) is
/// given: the capped, floored S_r and the peak of the softening. The parameters must be
/// resolved (blow count and φ′ set where the correlation needs them).
UndrainedStrength undrained_strength(const LiquefactionParameters& rule, double sigma_v0);

/// True when a point with the pore-pressure ratio maximum `max_ru` and the deviatoric
/// strain invariant `eps_q` meets the material's rule.
bool is_liquefied(const LiquefactionParameters& rule, double max_ru, double eps_q);

/// The cohesion of a liquefied point: S_r, or during the softening the linear
/// interpolation from the peak at εq^p = εq^p_0 to S_r at γ = √3 (εq^p − εq^p_0) = γ_s.
double cohesion(const Vec4& record, double plastic_shear_strain, double softening_strain);

/// Fills a liquefied point's record.
Vec4 make_record(const UndrainedStrength& strength, double plastic_shear_strain, double sigma_v0);

}  // namespace slide::liquefaction
