// One-dimensional MPM shape functions on a uniform grid, in cell units: ξ = (x − x0)/h,
// node k sits at ξ = k. The 2D weight of node (k, l) is the tensor product
// N_kl(x) = S_k(ξ) S_l(η), its gradient (S'_k S_l, S_k S'_l)/h.
//
// Linear (the classic MPM hat): particle in cell c = ⌊ξ⌋, f = ξ − c ∈ [0, 1),
//   S_c = 1 − f, S_{c+1} = f.
//
// uGIMP (Bardenhagen & Kober 2004, undeformed particle domain): the hat averaged over the
// particle's domain [ξ − a, ξ + a], a = l_p/(2h) ≤ ½ the half-length in cell units. Such
// a domain touches at most three nodes: the nearest node m = ⌊ξ + ½⌋ and its neighbours.
// With f = ξ − m ∈ [−½, ½) and the "smoothed ramp" (the average of max(0, s) over
// [f − a, f + a])
//   R(f) = (a + c)²/(4a) + max(f − a, 0),  c = clamp(f, −a, a),
// the weights are S_{m+1} = R(f), S_{m−1} = R(−f), S_m = 1 − R(f) − R(−f) (partition of
// unity by construction) and R'(f) = (a + c)/(2a). This is the standard piecewise form
// (linear where the domain sits inside one cell, quadratic where it straddles a node)
// written without branches, so the compiler can keep the kernels free of mispredictions.
#pragma once

#include <algorithm>
#include <cmath>

namespace slide::mpm {

/// Weights and ξ-derivatives of the `support` nodes starting at `base`.
template <int Support>
struct Weights1d {
  int base = 0;
  double value[Support];
  double derivative[Support];  ///< dS/dξ (divide by h for dS/dx)
};

struct LinearShape {
  static constexpr int support = 2;
  static Weights1d<2> weights(double xi, double /*half_size*/) {
    Weights1d<2> w;
    const double cell = std::floor(xi);
    const double f = xi - cell;
    w.base = static_cast<int>(cell);
    w.value[0] = 1.0 - f;
    w.value[1] = f;
    w.derivative[0] = -1.0;
    w.derivative[1] = 1.0;
    return w;
  }
};

struct GimpShape {
  static constexpr int support = 3;
  /// `half_size` a = l_p/(2h) in cell units, 0 < a ≤ ½.
  static Weights1d<3> weights(double xi, double half_size) {
    Weights1d<3> w;
    const double nearest = std::floor(xi + 0.5);
    const double f = xi - nearest;
    const double a = half_size;
    const double inv_4a = 0.25 / a;
    const double c_plus = std::clamp(f, -a, a);
    const double c_minus = -c_plus;  // clamp(−f, −a, a)
    const double ramp_plus = (a + c_plus) * (a + c_plus) * inv_4a + std::max(f - a, 0.0);
    const double ramp_minus = (a + c_minus) * (a + c_minus) * inv_4a + std::max(-f - a, 0.0);
    const double slope_plus = (a + c_plus) * (2.0 * inv_4a);
    const double slope_minus = (a + c_minus) * (2.0 * inv_4a);
    w.base = static_cast<int>(nearest) - 1;
    w.value[0] = ramp_minus;
    w.value[1] = 1.0 - ramp_plus - ramp_minus;
    w.value[2] = ramp_plus;
    w.derivative[0] = -slope_minus;
    w.derivative[1] = slope_minus - slope_plus;
    w.derivative[2] = slope_plus;
    return w;
  }
};

}  // namespace slide::mpm
