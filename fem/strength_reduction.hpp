// The factor of safety by strength reduction (docs/method.md §3, "Factor of safety"):
// the FE model of the case, its soils turned to Mohr–Coulomb with tan φ and c divided by
// a trial factor F, is released from its geostatic state with heavy local damping; it is
// in equilibrium at F when its kinetic energy has died out (KE at the end below 1e-4 of
// its peak) with every node within a tenth of the model's height of where it started,
// and has failed otherwise: it keeps moving, or it slid so far before something (the
// base, the wall) stopped it that it is a slide, not a settlement. Bisection on F between a stable
// and a failing trial, to a relative width of 0.5 %. F_s is the largest stable factor found.
#pragma once

#include <filesystem>
#include <vector>

#include "common/base/log.hpp"
#include "fem/fem_plan.hpp"

namespace slide {
struct Case;
}  // namespace slide

namespace slide::fem {

/// One trial factor: whether the reduced model reached equilibrium, and the measures
/// that decided it.
struct StrengthTrial {
  double factor = 1.0;
  bool stable = false;
  double ke_end_over_peak = 0.0;  ///< KE at the end over its peak
  double max_displacement = 0.0;  ///< largest nodal |u| at the end, m
  std::filesystem::path folder;   ///< the trial's outputs (history, last checkpoint)
};

struct StrengthReduction {
  double factor_of_safety = 0.0;      ///< the largest stable trial factor
  double failing_factor = 0.0;        ///< the smallest failing one (bisection's upper bound)
  double duration = 0.0;              ///< pseudo-time of each trial, s
  double height = 0.0;                ///< the mesh's height, m (the displacement threshold's scale)
  std::vector<StrengthTrial> trials;  ///< in the order they ran
};

/// Decision rule: equilibrium when KE at the end of the trial is below this share of its
/// peak (a stable body's KE decays by orders of magnitude under the local damping; a
/// failing one keeps moving at a roughly steady rate) ...
inline constexpr double equilibrium_energy_ratio = 1e-4;
/// ... and no node moved more than this share of the model's height. A stable slope
/// settles by its elastic and plastic redistribution (up to 1 % of its height measured:
/// 0.28 m of slope-seismic's 25 m at F = 1, Bishop's F 1.28); a failing one moves by
/// metres, and in small strain its mechanism can come to rest against the base's
/// contact plane, its energy dead, after sliding the height of the slope.
inline constexpr double equilibrium_displacement_ratio = 0.1;
/// Cundall local damping α of the trials (the usual choice for static solutions by
/// dynamic relaxation).
inline constexpr double strength_reduction_damping = 0.8;
/// Bisection stops when (F_fail − F_stable) / F_stable is below this.
inline constexpr double strength_reduction_tolerance = 0.005;

/// The element of the trials: the command line's (--element), else quad4-2x2 where the
/// case has the one-point quad, else the case's. The one-point quad's hourglass springs
/// stay elastic while the soil flows and hold shallow mechanisms back: on
/// cases/template it puts F_s at 1.34 where the 2×2 quad gives 0.91 and Bishop 0.82.
ElementType strength_reduction_element(const Case& c, const FemOptions& options);

/// The trial's verdict from its end state (the two thresholds above; `height` of the mesh).
bool in_equilibrium(double ke_end_over_peak, double max_displacement, double height);

/// The case with every material's FE model Mohr–Coulomb and tan φ, c (and ψ, which may
/// not exceed the reduced φ) divided by `factor`, and the base's friction coefficient
/// too (an interface of the soil: the shipped cases make it tan φ of the soil); Rayleigh
/// damping replaced by the local damping above, no base motion, the failure stage
/// lasting `duration` seconds.
Case reduced_case(const Case& c, double factor, double duration);

/// The mesh's height, max y − min y of its nodes, m.
double mesh_height(const Mesh& mesh);
/// The pseudo-time of a trial: 20 periods of the body's first shear mode, 4 H / Vs (H the
/// mesh's height, Vs of its softest material).
double strength_trial_duration(const Case& c, const Mesh& mesh);

/// Runs the trials into `options.output_dir`/F<factor>/ and writes
/// `strength_reduction.txt` (F_s, the criterion, every trial) there; logs one line per trial.
/// Error (one line) when F between 0.05 and 20 does not bracket the failure.
StrengthReduction run_strength_reduction(const Case& c, const FemOptions& options,
                                         const Logger& log);

}  // namespace slide::fem
