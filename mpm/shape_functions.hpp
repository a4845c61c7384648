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
//
// APIC moments (Jiang et al. 2015, "The affine particle-in-cell method"). APIC's
// inertia-like matrix D_p = Σ_i N_ip (x_i − x_p)(x_i − x_p)ᵀ is, for tensor-product
// weights that reproduce linear fields (Σ_k S_k (k − ξ) = 0), diagonal with the 1-D
// entries D = h² Σ_k S_k (k − ξ)²: the variance of the node positions under the weights.
// With the partition of unity and that reproduction it is D = h² (S_{−1} + S_{+1} − f²)
// over three nodes k = −1, 0, 1 (f from the middle one; S_{+1} − S_{−1} = f). It is h²/4
// everywhere for quadratic B-splines (uGIMP with l_p = h, a = ½), but not constant here:
//   linear  D = h² f(1 − f): 0 on a node line (singular), h²/4 at the cell centre;
//   uGIMP   D = h² (⟨f(1 − f)⟩ + a²/3) (the hat's variance averaged over the domain plus
//           the domain's own): a h²/2 on a node, h²/4 at the cell centre (a = ¼ at 2 × 2
//           particles per cell: D ∈ [h²/8, h²/4]; a = ⅛ at 4 × 4: [h²/16, h²/4]).
// `affine` returns D (cell units, × h² for m²), the first moments S_k (k − ξ) and the
// "affine weights" e_k = S_k (k − ξ)/D (× 1/h for 1/m) with which
//   Σ_i v_i (N_ip D_p⁻¹ (x_i − x_p))ᵀ, N_ip D_p⁻¹ (x_i − x_p) = (e_a S_b, S_a e_b)/h,
// is the affine velocity C_p = B_p D_p⁻¹. For linear hats e_k = dS_k/dξ exactly
// (S_c = 1 − f, k − ξ = −f: e_c = −(1 − f) f/(f(1 − f)) = −1; likewise +1), so C_p is the
// grid velocity gradient and no division by the vanishing D is ever needed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace slide::mpm {

/// ⌊x⌋ of a position in cell units. x86-64's baseline instruction set (SSE2) has no
/// rounding instruction, and std::floor there takes about 19 instructions; a truncation
/// corrected by one takes 6 and is exact for |x| < 2⁵² (any grid); other values, which a
/// located particle never has, go to std::floor. With SSE4.1 std::floor is one
/// instruction and is used as it is.
inline double floor_cells(double x) {
#if defined(__x86_64__) && !defined(__SSE4_1__)
  if (!(std::abs(x) < 0x1p52)) return std::floor(x);
  const double truncated = static_cast<double>(static_cast<std::int64_t>(x));
  return truncated > x ? truncated - 1.0 : truncated;
#else
  return std::floor(x);
#endif
}

/// Weights and ξ-derivatives of the `support` nodes starting at `base`.
template <int Support>
struct Weights1d {
  int base = 0;
  int cell = 0;  ///< ⌊ξ⌋ − base: the particle's cell starts at node base + cell
  double value[Support];
  double derivative[Support];  ///< dS/dξ (divide by h for dS/dx)
};

/// APIC's 1-D moments of the weights (see the header comment), in cell units.
template <int Support>
struct AffineWeights1d {
  double inertia;          ///< D = Σ_k S_k (k − ξ)² (× h² for m²)
  double moment[Support];  ///< S_k (k − ξ) (× h for m)
  double value[Support];   ///< e_k = S_k (k − ξ)/D (× 1/h for 1/m)
};

struct LinearShape {
  static constexpr int support = 2;
  static Weights1d<2> weights(double xi, double /*half_size*/) {
    Weights1d<2> w;
    const double cell = floor_cells(xi);
    const double f = xi - cell;
    w.base = static_cast<int>(cell);
    w.value[0] = 1.0 - f;
    w.value[1] = f;
    w.derivative[0] = -1.0;
    w.derivative[1] = 1.0;
    return w;
  }
  /// D = Σ_k S_k (k − ξ)² = f(1 − f).
  static double inertia(double xi, double /*half_size*/) {
    const double f = xi - floor_cells(xi);
    return f * (1.0 - f);
  }
  /// D = f(1 − f) and e_k = dS_k/dξ, the identity of the header comment.
  static AffineWeights1d<2> affine(const Weights1d<2>& w, double xi) {
    AffineWeights1d<2> m;
    const double f = xi - w.base;
    m.inertia = f * (1.0 - f);
    m.moment[0] = -m.inertia;  // (1 − f)(−f)
    m.moment[1] = m.inertia;   // f (1 − f)
    m.value[0] = w.derivative[0];
    m.value[1] = w.derivative[1];
    return m;
  }
};

/// The uGIMP half-length a particle at ξ (cell units) may use on a grid of `cells`
/// cells: at most its own, and no further than the grid's edge. Material does not extend
/// beyond the walls and the base; a domain that did would give the ghost node beyond the
/// edge a sliver of the particle's mass (weight (a − ξ)²/(4a)) but a share (a − ξ)/(2a)
/// of its gradient, and that node's velocity, set by a sliver of mass and a full share
/// of force, then leaks into the particle's velocity gradient. (column-short's lowest
/// particle row sits 0.069 h above the base with a = 0.087: under the crest it held
/// 40 % more than the overburden.) The domain shrinks symmetrically to the distance from
/// the edge, down to a floor that keeps 1/(4a) and APIC's D ≥ a/2 well conditioned; a
/// particle pressed through the edge (ξ < 0) keeps that floor.
inline double clipped_half_size(double xi, int cells, double half_size) {
  constexpr double floor = 1e-3;
  const double to_edge = std::min(xi, cells - xi);
  return std::min(half_size, std::max(to_edge, floor));
}

struct GimpShape {
  static constexpr int support = 3;
  /// `half_size` a = l_p/(2h) in cell units, 0 < a ≤ ½.
  static Weights1d<3> weights(double xi, double half_size) {
    Weights1d<3> w;
    const double nearest = floor_cells(xi + 0.5);
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
    // ⌊ξ⌋ is the nearest node or the one before it (ξ + ½ rounds up at most to the next
    // integer), and the sign of f is exact: this is ⌊ξ⌋ − base with no second floor.
    w.cell = f >= 0.0 ? 1 : 0;
    w.value[0] = ramp_minus;
    w.value[1] = 1.0 - ramp_plus - ramp_minus;
    w.value[2] = ramp_plus;
    w.derivative[0] = -slope_minus;
    w.derivative[1] = slope_minus - slope_plus;
    w.derivative[2] = slope_plus;
    return w;
  }
  /// D = Σ_k S_k (k − f)² over the nodes k = −1, 0, 1 (f from the nearest node). The
  /// partition of unity and Σ_k S_k (k − f) = 0 (S_{+1} − S_{−1} = f) reduce it to
  /// D = S_{−1} + S_{+1} − f², which is never below a/2 (a particle centred on a node).
  static double inertia(const Weights1d<3>& w, double xi) {
    const double f = xi - (w.base + 1);  // from the nearest node, as in `weights`
    return w.value[0] + w.value[2] - f * f;
  }
  static double inertia(double xi, double half_size) { return inertia(weights(xi, half_size), xi); }
  /// D and e_k = S_k (k − f)/D: a plain division, D ≥ a/2.
  static AffineWeights1d<3> affine(const Weights1d<3>& w, double xi) {
    AffineWeights1d<3> m;
    const double f = xi - (w.base + 1);
    m.inertia = inertia(w, xi);
    const double inv_inertia = 1.0 / m.inertia;
    for (int k = 0; k < 3; ++k) {
      m.moment[k] = w.value[k] * ((k - 1) - f);
      m.value[k] = m.moment[k] * inv_inertia;
    }
    return m;
  }
};

}  // namespace slide::mpm
