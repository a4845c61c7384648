// The saturated soil's state through the transfer (docs/method.md §10).
//
// Each particle of a model with pore water receives
//   - p (already interpolated from the nodes by its element's shape functions, as every
//     nodal field) and Δp = p − p_static with p_static interpolated the same way;
//   - σ′v0, p′₀ and r_u,max from its element's nearest Gauss point: they are the state
//     before the shaking and a maximum over the FE history, quantities a smooth
//     interpolant would blur or overshoot, so they come as the FE had them;
//   - the liquefied flag of its material's rule (r_u,max, or γ = √3 εq of the transferred
//     strain), and for a liquefied particle of a material with a residual-strength
//     correlation the record of its undrained strength (S_peak, S_r, εq^p now, σ′v0).
// The stress stays effective (σ′); the pore pressure is a field of its own and the MPM
// phase forms σ′ − p I in its forces: p is counted once.
#pragma once

#include <cstddef>
#include <span>

#include "common/io/checkpoint.hpp"
#include "transfer/transfer_report.hpp"

namespace slide::transfer {

/// Fills the particles' pore-water fields and liquefaction state; `xi` are their
/// reference coordinates in their elements, `source` their elements' nearest Gauss points,
/// `materials` the FE checkpoint's with the transfer's overrides, `assumed[id]` true for
/// a material whose every particle is liquefied (--assume-liquefied).
void carry_pore_water(const FemCheckpoint& fem, const MaterialTable& materials,
                      const std::vector<bool>& assumed, std::span<const Vec2> xi,
                      std::span<const std::size_t> source, Particles& particles,
                      PoreWaterReport& report);

}  // namespace slide::transfer
