// The instability guard of the FE phase (METHOD.md §5 applies to both solvers).
//
// At every output step, before anything is written, the state must pass three checks:
//  1. finite: every displacement, velocity, stress and hourglass force is finite;
//  2. speed: no node moves faster than fem.speed_limit_factor · sqrt(2 g H), H the
//     height of the model (a body falling its own height reaches sqrt(2 g H); a few
//     times that is beyond any physical motion of the slide);
//  3. energy: the total energy E = KE + (PE − PE_0) + stored elastic + hourglass energy
//     does not grow beyond its value at the start of the failure stage by more than 1 %
//     of the energy scale (the potential energy the body could release by falling to
//     its lowest point, plus the initial stored and kinetic energy). Gravity is
//     conservative and plasticity, friction and damping only dissipate, so E can only
//     fall; the leapfrog scheme conserves a modified energy that differs from E by
//     O((ω dt)²) ≈ 10⁻³ of the energy in the resolved modes at C = 0.5, an order of
//     magnitude below the tolerance, while a numerical instability grows exponentially
//     and crosses it within a few steps.
// A failed check is a one-line diagnosis: which check, where (node or Gauss point and
// its position) and when.
#pragma once

#include <string>
#include <vector>

#include "fem/fem_model.hpp"

namespace slide::fem {

struct GuardLimits {
  double speed_limit = 0.0;        ///< m/s
  double initial_energy = 0.0;     ///< E at the start of the failure stage, J/m
  double energy_scale = 0.0;       ///< J/m
  double energy_tolerance = 0.01;  ///< allowed growth, fraction of energy_scale
};

/// Empty when the state is sound, otherwise the diagnosis ("... at t = 1.234 s").
std::string check_stability(const FemModel& model, const FemState& state,
                            std::span<const Vec2> coordinates, double total_energy,
                            const GuardLimits& limits);

}  // namespace slide::fem
