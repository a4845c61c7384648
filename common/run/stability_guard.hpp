// The instability guard of both stages (docs/method.md §5). At every output step, before
// anything is written, the state must pass three checks:
//  1. finite: every field of the state is finite;
//  2. speed: nothing moves faster than speed_limit_factor · sqrt(2 g H), H the height of
//     the body (a body falling its own height reaches sqrt(2 g H); a few times that is
//     beyond any physical motion of a slide);
//  3. energy: the total energy E = KE + (PE − PE_0) + stored energy does not grow beyond
//     its value at the start of the stage by more than 5 % of the energy scale (the
//     potential energy the body could release by falling to its lowest point, plus the
//     initial stored and kinetic energy).
// Gravity is conservative and plasticity, friction and damping only dissipate, so E can
// only fall up to discretisation errors: the leapfrog scheme of the FE phase conserves
// a modified energy within O((ω dt)²) ≈ 10⁻³ of it at C = 0.5, MPM's cell crossings
// add errors of the order of one per cent (the vibrating bar drifts by < 0.1 %). A run
// that blows up grows its energy exponentially and crosses any such tolerance within a
// few steps, so one tolerance, 5 %, serves both stages with a wide margin on both sides.
// The finite and speed checks know the solver's own fields and live with it; this
// header holds what they share, and the error a failed check throws.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "common/base/error.hpp"

namespace slide::run {

/// A failed check: one line naming the check, where and when, and the last good
/// checkpoint.
class InstabilityError : public Error {
 public:
  using Error::Error;
};

/// The allowed growth of the total energy, as a fraction of the energy scale.
inline constexpr double energy_growth_tolerance = 0.05;

/// The energy check's references, fixed at the start of a stage and carried by restarts.
struct EnergyReference {
  double initial_energy = 0.0;  ///< E at the start of the stage, J/m
  double energy_scale = 0.0;    ///< the energy the body can release, J/m
};

/// The speed bound factor · sqrt(2 g H), m/s.
inline double speed_limit(double factor, double gravity, double height) {
  return factor * std::sqrt(2.0 * gravity * height);
}

/// Empty when `total_energy` is finite and within the tolerance, otherwise the diagnosis
/// ("total energy grew by …"; `parts` names what it is made of, e.g. "kinetic 1.2e5 +
/// potential + elastic 3e4 J/m").
std::optional<std::string> energy_growth(double total_energy, const EnergyReference& reference,
                                         const std::string& parts = {});

}  // namespace slide::run
