// Measuring a run (METHOD.md §6): surface profile, toe, runout, crest height and the
// profile RMSE against a reference run. Shared by mpm-solve (history columns) and the
// metrics tool, so both report the same numbers.
//
//  - Profile: vertical bins of width w from the wall x = 0; bin b covers [b w, (b+1) w).
//    Its height is the p-th percentile (default 99th, linear interpolation between order
//    statistics) of the y of its particles.
//  - Toe: the largest particle x within the run of contiguous non-empty bins that starts
//    at the wall; particles beyond an empty bin are strays and are ignored.
//  - Runout R = x_toe − L0, R_N = R / L0; crest height H_c = height of the first bin.
//  - RMSE = sqrt( (1/N_b) Σ_b ((y_b − y_b,ref)/(y_b,ref + p))² ) over the bins from the
//    wall to the one holding the reference toe; p = particle size. A bin the run does not
//    reach (empty, or beyond its own toe) has height 0.
#pragma once

#include <span>
#include <vector>

#include "common/types.hpp"

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
};

/// Profile of the particles above `foundation_level` (METHOD.md §6 uses all of them:
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

/// Profile RMSE of `run` against `reference` (METHOD.md §6).
double profile_rmse(const SurfaceProfile& run, const SurfaceProfile& reference,
                    double particle_size);

}  // namespace slide
