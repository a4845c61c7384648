// How a case measures a run ([metrics] of case.toml, docs/method.md §6): the initial
// column or slope dimensions and the surface profile's bins.
#pragma once

namespace slide {

struct MetricsSpec {
  double initial_length = 0.0;  ///< L_0, m
  double initial_height = 0.0;  ///< H_0, m (τ_c = sqrt(H_0/g))
  double bin_width = 2.0;       ///< profile bins, m
  double profile_percentile = 99.0;
  /// Particles at or below this height are left out of the profile and the toe: the
  /// top of a foundation layer that stays in place (slope-cohesive), m. 0: none.
  double foundation_level = 0.0;
};

}  // namespace slide
