// The FE phase's side of the instability guard (common/run/stability_guard.hpp holds
// the checks, the tolerance and their reasons): at every output step the displacements,
// velocities, stresses and hourglass forces must be finite, no node may move faster than
// fem.speed_limit_factor · sqrt(2 g H), and the total energy E = KE + (PE − PE_0) +
// stored elastic + hourglass energy must not grow beyond the shared tolerance. A failed
// check is a one-line diagnosis: which check, where (node or Gauss point and its
// position) and when.
#pragma once

#include <string>
#include <vector>

#include "common/run/stability_guard.hpp"
#include "fem/fem_model.hpp"

namespace slide::fem {

struct GuardLimits {
  double speed_limit = 0.0;     ///< m/s
  run::EnergyReference energy;  ///< E and the energy scale at the start of the failure stage
};

/// Empty when the state is sound, otherwise the diagnosis ("... at t = 1.234 s").
std::string check_stability(const FemModel& model, const FemState& state,
                            std::span<const Vec2> coordinates, double total_energy,
                            const GuardLimits& limits);

}  // namespace slide::fem
