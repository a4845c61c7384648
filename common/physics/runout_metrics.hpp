// Measuring a run (docs/method.md §6): surface profile, toe, runout, crest height and the
// profile RMSE against a reference run. Shared by mpm-solve (history columns) and the
// metrics tool, so both report the same numbers.
//
//  - Profile: vertical bins of width w from the wall x = 0; bin b covers [b w, (b+1) w).
//    Its height is the p-th percentile (default 99th, linear interpolation between order
//    statistics) of the y of its particles.
//  - Toe: the largest particle x within the run of contiguous non-empty bins that starts
//    at the wall; particles beyond an empty bin are strays and are ignored.
//  - Runout R = x_toe − L0, R_N = R / L0; crest height H_c = height of the first bin.
//  - Front of a share s of the mass (default 95 %): x_s, the smallest x with a share s
//    of the measured mass (the particles the profile measures) at or behind it. The
//    sheet beyond it: from x_s to the toe, its length x_toe − x_s, its share of the mass
//    (about 1 − s: a particle's mass is not split) and its mean thickness, its particles'
//    area over its length. The extreme toe of a slide that ends in a film of particles
//    is the film's; x_s is the body's front.
//  - RMSE = sqrt( (1/N_b) Σ_b ((y_b − y_b,ref)/(y_b,ref + p))² ) over the bins from the
//    wall to the one holding the reference toe; p = particle size. A bin the run does not
//    reach (empty, or beyond its own toe) has height 0.
//  - Stress quality at rest: how far the vertical stress of the deposit is from the
//    lithostatic stress under the measured surface, e_p = |σyy,p − σyy,lith(x_p)| /
//    (ρ g H0) with σyy,lith = −ρ g (h_b − y_p), h_b the profile height of the particle's
//    bin and ρ its material's density; its 50th, 90th, 99th percentiles and maximum over
//    the deposit. The deposit is the particles at rest (speed < 1 cm/s) that the profile
//    takes its heights from: over a foundation layer (foundation_level > 0) the material
//    above the level (and all of a crest sunk below it), not the layer below the debris,
//    as for the runout; strays beyond the toe have no h_b and are left out. A deposit that
//    carries just its own weight has e ≈ 0; what remains is stress the runout left behind
//    or made up (arching, locked-in shear, particle-to-particle stress noise). h_b is a
//    percentile of particle centres, at best half a particle spacing p below the body's
//    top edge, so the exact lithostatic field under that edge shows e ≈ p / (2 H0) at
//    every depth (0.3 % for column-short): the floor of the measure.
#pragma once

#include <limits>
#include <span>
#include <vector>

#include "common/base/types.hpp"

namespace slide {

/// p-th percentile (0 < p ≤ 100) of `values`, linear interpolation between order
/// statistics: the value at rank (p/100)(n − 1) of the sorted sample. NaN when empty.
double percentile(std::vector<double> values, double p);

struct SurfaceProfile {
  double bin_width = 2.0;
  /// Height of each bin from the wall up to the toe's bin (the contiguous run): bins
  /// beyond the toe are not listed.
  std::vector<double> height;
  double x_toe = 0.0;
  std::size_t stray_count = 0;  ///< particles beyond the first empty bin
  /// Over a foundation: the first bin with material above the foundation level. The
  /// bins before it (a crest sunk below the level) have the height of all their
  /// particles; from it on, only the particles above the level count. 0 without one.
  std::size_t first_above_level = 0;
};

/// Profile of the particles above `foundation_level` (docs/method.md §6 uses all of them:
/// level 0; a foundation layer that fills every bin to the grid's end would otherwise
/// put the toe there). Over a foundation (level > 0) the contiguous run of bins starts
/// at the first bin with material above the level, and the bins between the wall and it
/// (a crest that has sunk below the level) get the height of all their particles (0 if
/// they have none).
SurfaceProfile surface_profile(std::span<const Vec2> points, double bin_width,
                               double percentile_p = 99.0, double foundation_level = 0.0);

struct RunoutMeasures {
  double x_toe = 0.0;
  double runout = 0.0;             ///< R = x_toe − L0
  double runout_normalised = 0.0;  ///< R_N = R / L0
  double crest_height = 0.0;       ///< H_c
};

RunoutMeasures runout_measures(const SurfaceProfile& profile, double initial_length);

struct FrontMeasures {
  double share = 0.95;            ///< s
  double x_front = 0.0;           ///< x_s, m
  double sheet_length = 0.0;      ///< x_toe − x_s, m
  double sheet_mass_share = 0.0;  ///< mass beyond x_s over the measured mass
  double sheet_thickness = 0.0;   ///< area beyond x_s over the sheet's length, m (0 if none)
};

/// The front of a share `share` of the mass and the sheet beyond it (above), over the
/// particles `profile` measures (measured_by_profile with `foundation_level`). Masses
/// in kg/m, volumes in m³/m, one per point.
FrontMeasures front_measures(std::span<const Vec2> points, std::span<const double> masses,
                             std::span<const double> volumes, const SurfaceProfile& profile,
                             double foundation_level, double share = 0.95);

/// Profile RMSE of `run` against `reference` (docs/method.md §6).
double profile_rmse(const SurfaceProfile& run, const SurfaceProfile& reference,
                    double particle_size);

/// Whether the particle at `x` is one of those `profile` (made with this
/// `foundation_level`) took its heights from: x ≥ 0, in a bin of the contiguous run, and
/// above the foundation level unless its bin is one of the sunk crest bins before
/// `profile.first_above_level` (where all particles count).
bool measured_by_profile(const Vec2& x, const SurfaceProfile& profile, double foundation_level);

/// Speed below which a particle counts as at rest, part of the deposit (docs/method.md §6).
inline constexpr double rest_speed = 0.01;  // m/s

struct StressQuality {
  std::size_t deposit_count = 0;  ///< particles measured (at rest and measured by the profile)
  // Percentiles of e_p (linear interpolation, as `percentile`); NaN without a deposit.
  double p50 = std::numeric_limits<double>::quiet_NaN();
  double p90 = std::numeric_limits<double>::quiet_NaN();
  double p99 = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

/// The particle errors e_p = |σyy,p − σyy,lith(x_p)| / (ρ_p g H0) of the deposit,
/// σyy,lith = −ρ_p g (h_b − y_p) with h_b = profile.height of the particle's bin, in
/// particle order. The deposit: particles with |v| < rest_speed that `profile` measures
/// (measured_by_profile: over a foundation layer, the material above its level; the
/// layer itself is not the slide's deposit and strays beyond the toe have no h_b).
/// σyy tension positive (compression negative), Pa; densities kg/m³ per particle.
std::vector<double> stress_errors_at_rest(std::span<const Vec2> coordinates,
                                          std::span<const Vec2> velocities,
                                          std::span<const double> sigma_yy,
                                          std::span<const double> densities,
                                          const SurfaceProfile& profile, double initial_height,
                                          double foundation_level = 0.0);

/// The percentiles and maximum of stress_errors_at_rest (docs/method.md §6).
StressQuality stress_quality_at_rest(std::span<const Vec2> coordinates,
                                     std::span<const Vec2> velocities,
                                     std::span<const double> sigma_yy,
                                     std::span<const double> densities,
                                     const SurfaceProfile& profile, double initial_height,
                                     double foundation_level = 0.0);

}  // namespace slide
