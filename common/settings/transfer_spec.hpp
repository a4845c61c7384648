// The transfer's settings as a case gives them ([transfer] of case.toml): the particle
// layout per element, the interpolation of Gauss-point fields, the sweep's transfer times.
#pragma once

#include <optional>
#include <vector>

#include "common/physics/algorithms.hpp"

namespace slide {

struct TransferSpec {
  int particles_x = 4;          ///< N_px (quads)
  int particles_y = 4;          ///< N_py (quads)
  int particles_triangle = 16;  ///< points of the triangle rule
  StressInterpolation stress_interpolation = StressInterpolation::rbf;
  std::optional<RbfPolynomial> rbf_polynomial;  ///< unset: none for rbf, linear for rbf-local
  double rbf_shape = 0.0;                       ///< c, m (0: the default sqrt(A_box/N_g))
  int rbf_neighbours = 0;                       ///< k of rbf-local (0: the default)
  /// Transfer times the case's sweep uses, s (docs/method.md §7), and the one the main
  /// pipeline uses.
  std::vector<double> sweep_times;
  double main_time = 0.0;
};

}  // namespace slide
