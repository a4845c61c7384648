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
#include <cstring>

#include "common/base/pair.hpp"

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

/// floor_cells of both lanes, for positions of particles on the grid (|x| < 2³¹: the
/// grid's node indices are ints): a truncation to 32-bit integers corrected by one.
inline Pair floor_cells(Pair x) {
  using Int2 = std::int32_t __attribute__((vector_size(8)));
  const Pair truncated = __builtin_convertvector(__builtin_convertvector(x, Int2), Pair);
  return truncated > x ? truncated - 1.0 : truncated;
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

/// The weights of both axes of a particle, computed side by side (the kernels' path):
/// lane 0 of every pair is the x axis's, lane 1 the y axis's. Only the nodes the
/// particle's domain reaches are kept, from the first of them: `count` nodes of each
/// axis from `base`, value[0, count), the slots beyond count 0. A node the domain does not
/// reach has weight and derivative exactly 0 (GimpShape::weights); it would add ±0 to
/// every sum, which leaves a sum's bits as they are, so the kernels skip it. Each pair is
/// stored and loaded with one instruction.
template <int Support>
struct Weights2d {
  int base[2] = {};                   ///< the first reached node of x and of y
  int cell[2] = {};                   ///< ⌊ξ⌋ − base, ⌊η⌋ − base
  int count[2] = {Support, Support};  ///< the reached nodes of x and of y
  int skipped[2] = {};                ///< unreached nodes before base: base − Weights1d::base
  Pair value[Support];
  Pair derivative[Support];
  /// The position from the node the weights are written about, in cell units: uGIMP
  /// f = ξ − m (the nearest node, Weights1d::base + 1), linear f = ξ − base (APIC's moments
  /// use it).
  Pair offset;

  /// Where node k of one axis's whole stencil (Weights1d's numbering) is kept here, or −1
  /// for a node the domain does not reach.
  int slot(int lane, int k) const {
    const int kept = k - skipped[lane];
    return kept >= 0 && kept < count[lane] ? kept : -1;
  }
  /// One axis's weights on its whole stencil (0: x, 1: y), the unreached nodes' zeros put
  /// back: the numbers of Weights1d.
  Weights1d<Support> axis(int lane) const {
    Weights1d<Support> w;
    w.base = base[lane] - skipped[lane];
    w.cell = cell[lane] + skipped[lane];
    for (int k = 0; k < Support; ++k) {
      const int kept = slot(lane, k);
      w.value[k] = kept >= 0 ? value[kept][lane] : 0.0;
      w.derivative[k] = kept >= 0 ? derivative[kept][lane] : 0.0;
    }
    return w;
  }
};

/// APIC's moments of both axes, lane 0 x and lane 1 y, for the reached nodes of their
/// Weights2d (AffineWeights1d per axis).
template <int Support>
struct AffineWeights2d {
  Pair inertia;
  Pair moment[Support];
  Pair value[Support];

  /// One axis's moments on its whole stencil, given its weights (Weights2d::axis).
  AffineWeights1d<Support> axis(const Weights2d<Support>& w, int lane) const {
    AffineWeights1d<Support> m;
    m.inertia = inertia[lane];
    for (int k = 0; k < Support; ++k) {
      const int kept = w.slot(lane, k);
      m.moment[k] = kept >= 0 ? moment[kept][lane] : 0.0;
      m.value[k] = kept >= 0 ? value[kept][lane] : 0.0;
    }
    return m;
  }
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
  /// Both axes (the uGIMP interface; linear hats are cheap enough one axis at a time).
  static void weights(Pair xi, Pair half_size, Weights2d<2>& w) {
    const Weights1d<2> x = weights(xi[0], half_size[0]);
    const Weights1d<2> y = weights(xi[1], half_size[1]);
    w.base[0] = x.base;
    w.base[1] = y.base;
    for (int k = 0; k < 2; ++k) {
      w.value[k] = Pair{x.value[k], y.value[k]};
      w.derivative[k] = Pair{x.derivative[k], y.derivative[k]};
    }
    w.offset = xi - Pair{double(x.base), double(y.base)};  // count 2, nothing skipped
  }
  /// D = Σ_k S_k (k − ξ)² = f(1 − f).
  static double inertia(double xi, double /*half_size*/) {
    const double f = xi - floor_cells(xi);
    return f * (1.0 - f);
  }
  /// D = f(1 − f) and e_k = dS_k/dξ, the identity of the header comment.
  static AffineWeights1d<2> affine(const Weights1d<2>& w, double xi) {
    return affine_of(w, xi - w.base);
  }
  /// `affine` from f = ξ − base.
  static AffineWeights1d<2> affine_of(const Weights1d<2>& w, double f) {
    AffineWeights1d<2> m;
    m.inertia = f * (1.0 - f);
    m.moment[0] = -m.inertia;  // (1 − f)(−f)
    m.moment[1] = m.inertia;   // f (1 − f)
    m.value[0] = w.derivative[0];
    m.value[1] = w.derivative[1];
    return m;
  }
  static void affine(const Weights2d<2>& w, AffineWeights2d<2>& m) {
    const AffineWeights1d<2> x = affine_of(w.axis(0), w.offset[0]);
    const AffineWeights1d<2> y = affine_of(w.axis(1), w.offset[1]);
    m.inertia = Pair{x.inertia, y.inertia};
    for (int k = 0; k < 2; ++k) {
      m.moment[k] = Pair{x.moment[k], y.moment[k]};
      m.value[k] = Pair{x.value[k], y.value[k]};
    }
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
template <class Real>
Real clipped_half_size(Real xi, Real cells, Real half_size) {
  const Real floor = Real{} + 1e-3;
  const Real to_edge = lanes::min(xi, cells - xi);
  return lanes::min(half_size, lanes::max(to_edge, floor));
}
inline double clipped_half_size(double xi, int cells, double half_size) {
  return clipped_half_size<double>(xi, cells, half_size);
}

struct GimpShape {
  static constexpr int support = 3;

  /// The weights' arithmetic for one axis (Real = double) or for both axes at once
  /// (Real = Pair: each lane does the double's operations in the same order).
  template <class Real>
  struct Terms {
    Real nearest;  ///< m = ⌊ξ + ½⌋
    Real f;        ///< ξ − m
    Real value[3], derivative[3];
  };
  template <class Real>
  static Terms<Real> terms(Real xi, Real a) {
    Terms<Real> t;
    const Real zero{};
    t.nearest = floor_cells(xi + 0.5);
    t.f = xi - t.nearest;
    const Real inv_4a = 0.25 / a;
    const Real c_plus = lanes::clamp(t.f, -a, a);
    const Real c_minus = -c_plus;  // clamp(−f, −a, a)
    const Real ramp_plus = (a + c_plus) * (a + c_plus) * inv_4a + lanes::max(t.f - a, zero);
    const Real ramp_minus = (a + c_minus) * (a + c_minus) * inv_4a + lanes::max(-t.f - a, zero);
    const Real slope_plus = (a + c_plus) * (2.0 * inv_4a);
    const Real slope_minus = (a + c_minus) * (2.0 * inv_4a);
    t.value[0] = ramp_minus;
    t.value[1] = 1.0 - ramp_plus - ramp_minus;
    t.value[2] = ramp_plus;
    t.derivative[0] = -slope_minus;
    t.derivative[1] = slope_minus - slope_plus;
    t.derivative[2] = slope_plus;
    return t;
  }

  /// `half_size` a = l_p/(2h) in cell units, 0 < a ≤ ½.
  static Weights1d<3> weights(double xi, double half_size) {
    const Terms<double> t = terms(xi, half_size);
    Weights1d<3> w;
    w.base = static_cast<int>(t.nearest) - 1;
    // ⌊ξ⌋ is the nearest node or the one before it (ξ + ½ rounds up at most to the next
    // integer), and the sign of f is exact: this is ⌊ξ⌋ − base with no second floor.
    w.cell = t.f >= 0.0 ? 1 : 0;
    std::copy_n(t.value, 3, w.value);
    std::copy_n(t.derivative, 3, w.derivative);
    return w;
  }
  /// The weights of both axes, ξ = (ξ, η) and a = (a_x, a_y), of a particle on the grid
  /// (floor_cells of a pair): lane by lane the bits of `weights`.
  static void weights(Pair xi, Pair half_size, Weights2d<3>& w) {
    const Terms<Pair> t = terms(xi, half_size);
    // A domain inside one cell (|f| ≥ a) does not reach the node beyond the nearest one
    // on its far side, and its weight and derivative there are exactly ±0: f ≥ a gives
    // clamp(−f, −a, a) = −a, so R(−f) = (a − a)²/(4a) + max(−f − a, 0) = +0 and R'(−f) = 0
    // (f ≤ −a likewise for R(f)). With column-short's 4 × 4 particles a cell (a = ⅛)
    // that is three axes in four: most stencils are 2 × 2. An unreached node m − 1 is
    // skipped by starting at m.
    const Mask below = t.f >= half_size;   // node m − 1 unreached
    const Mask above = t.f <= -half_size;  // node m + 1 unreached
    const Pair zero{};
    w.value[0] = below ? t.value[1] : t.value[0];
    w.value[1] = below ? t.value[2] : t.value[1];
    w.value[2] = below ? zero : t.value[2];
    w.derivative[0] = below ? t.derivative[1] : t.derivative[0];
    w.derivative[1] = below ? t.derivative[2] : t.derivative[1];
    w.derivative[2] = below ? zero : t.derivative[2];
    w.offset = t.f;
    // Both lanes' integers at once: the nearest nodes truncated (they are whole numbers),
    // and the masks (all bits set, −1, where they hold) negated.
    using Int2 = std::int32_t __attribute__((vector_size(8)));
    const Int2 skipped = -__builtin_convertvector(below, Int2);
    const Int2 base = __builtin_convertvector(t.nearest, Int2) - 1 + skipped;
    // ⌊ξ⌋ is the nearest node or the one before it (ξ + ½ rounds up at most to the next
    // integer), and the sign of f is exact: ⌊ξ⌋ − base with no second floor.
    const Int2 cell = -__builtin_convertvector(t.f >= 0.0, Int2) - skipped;
    const Int2 count = 3 - skipped + __builtin_convertvector(above, Int2);
    std::memcpy(w.base, &base, sizeof base);
    std::memcpy(w.cell, &cell, sizeof cell);
    std::memcpy(w.count, &count, sizeof count);
    std::memcpy(w.skipped, &skipped, sizeof skipped);
  }
  /// D = Σ_k S_k (k − f)² over the nodes k = −1, 0, 1 (f from the nearest node). The
  /// partition of unity and Σ_k S_k (k − f) = 0 (S_{+1} − S_{−1} = f) reduce it to
  /// D = S_{−1} + S_{+1} − f², which is never below a/2 (a particle centred on a node);
  /// affine_terms computes it (f from the nearest node, as in `weights`).
  static double inertia(const Weights1d<3>& w, double xi) { return affine(w, xi).inertia; }
  static double inertia(double xi, double half_size) { return inertia(weights(xi, half_size), xi); }
  /// D, the moments S_k (k − f) and e_k = S_k (k − f)/D (a plain division, D ≥ a/2) from
  /// the weights, f and the end nodes' weights S_{−1}, S_{+1}, for one axis or both at
  /// once (as `terms`). `value` starts `skipped` nodes after node −1 (Weights2d), so
  /// value[k] is the weight of node k + skipped − 1 from the nearest.
  template <class Real>
  static void affine_terms(const Real (&value)[3], Real f, Real lower, Real upper, Real skipped,
                           Real& inertia, Real (&moment)[3], Real (&affine_value)[3]) {
    inertia = lower + upper - f * f;
    const Real inv_inertia = 1.0 / inertia;
    for (int k = 0; k < 3; ++k) {
      moment[k] = value[k] * ((double(k - 1) + skipped) - f);
      affine_value[k] = moment[k] * inv_inertia;
    }
  }
  static AffineWeights1d<3> affine(const Weights1d<3>& w, double xi) {
    AffineWeights1d<3> m;
    affine_terms(w.value, xi - (w.base + 1), w.value[0], w.value[2], 0.0, m.inertia, m.moment,
                 m.value);
    return m;
  }
  /// Both axes, for the reached nodes: lane by lane the bits of `affine` (f = ξ − (base
  /// + 1) is the weights' offset, the same number). Reached node k is node k + skipped − 1
  /// from the nearest, and where m − 1 was skipped its S = +0 enters D as it did there.
  static void affine(const Weights2d<3>& w, AffineWeights2d<3>& m) {
    const Pair skipped{double(w.skipped[0]), double(w.skipped[1])};
    const Mask shifted = skipped != 0.0;
    const Pair zero{};
    const Pair lower = shifted ? zero : w.value[0];        // S_{−1}
    const Pair upper = shifted ? w.value[1] : w.value[2];  // S_{+1}
    affine_terms(w.value, w.offset, lower, upper, skipped, m.inertia, m.moment, m.value);
  }
};

}  // namespace slide::mpm
