// The transfer: the FE model at t_T becomes material points (docs/method.md §4).
//
// For every element, the particles of its layout (particle_layout.hpp) at reference
// points ξ_p with shares w_p (Σ w_p = 1 per element) receive
//   - nodal fields by the element's own shape functions on the current nodes:
//       x_p = Σ_k N_k(ξ_p) x_k, and likewise u_p, v_p and the pore pressure;
//   - Gauss-point fields (stress with σzz, strain, model state) by interpolation over
//     the current Gauss point positions: global multiquadric RBF ("rbf"), the same over
//     the k nearest Gauss points ("rbf-local"), or the owning element's nearest Gauss
//     point ("element", the baseline). εq is recomputed from the transferred strain;
//   - volume from the deformed element, mass from the undeformed one:
//       V_p = V_t^e w_p,  M_p = ρ V_0^e w_p,
//     so Σ M_p = Σ ρ V_0^e exactly and Σ V_p = Σ V_t^e exactly;
//   - the GIMP domain l_x = l_y = sqrt(V_p): a square of the particle's own volume;
//   - its element's material, and the element index as its origin.
// An element inverted at t_T (is_inverted of common/geometry/element.hpp, the definition fem-solve
// counts with: det J ≤ 0 at one of its corners, hence somewhere in the element) stops
// the transfer with an error naming it; with `allow_inverted` its particles get the
// reference volume V_0^e w_p instead (the inverted geometry defines no volume) and the
// report lists it. A checkpoint with V_t^e ≤ 0 for an element that is not inverted is
// inconsistent and refused.
// A collapsed element (inverted, or V_t^e < r V_0^e) keeps its particles, mass and
// nodal fields, but its Gauss points are left out of the RBF centres: a Gauss point of an
// element squashed flat sits on top of its neighbours' with an unrelated stress, and the
// multiquadric through such pairs swings (and its dense system loses all conditioning).
// Its particles take the fields interpolated from the other elements.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "common/base/log.hpp"
#include "common/io/checkpoint.hpp"
#include "common/settings/transfer_spec.hpp"
#include "transfer/particle_layout.hpp"
#include "transfer/transfer_report.hpp"

namespace slide::transfer {

/// k of rbf-local when the user gives none; justified in transfer/README.md by the
/// measurement of tools/benchmarks/transfer (bench_transfer neighbours).
inline constexpr int default_rbf_neighbours = 16;

/// r of TransferOptions::collapsed_volume_ratio when the user gives none; chosen in
/// transfer/README.md ("Collapsed elements") from the column-short measurement.
inline constexpr double default_collapsed_volume_ratio = 0.2;

struct TransferOptions {
  ParticlesPerElement particles;
  StressInterpolation stress_interpolation = StressInterpolation::rbf;
  /// Unset: none for rbf (the paper's form), linear for rbf-local.
  std::optional<RbfPolynomial> rbf_polynomial;
  double rbf_shape = 0.0;  ///< c, m; 0: sqrt(A_box / N_g) of the current Gauss points
  int rbf_neighbours = 0;  ///< k; 0: default_rbf_neighbours
  bool allow_inverted = false;
  /// Elements that kept less than this share of their volume (V_t^e < r V_0^e), and
  /// inverted ones, are collapsed: their Gauss points are not RBF centres. 0: only
  /// inverted elements.
  double collapsed_volume_ratio = default_collapsed_volume_ratio;
  /// Largest dense RBF matrix allowed, bytes; 0: 3/4 of MemAvailable, at most 16 GiB.
  std::size_t dense_memory_limit = 0;
  /// Saturated models (transfer/pore_water.hpp): materials whose every particle is taken
  /// as liquefied whatever its r_u,max (a zone known to have liquefied: the classical
  /// post-earthquake analysis), and a residual-strength correlation that replaces every
  /// material's own (unset: their own).
  std::vector<std::string> assume_liquefied;
  std::optional<ResidualStrengthCorrelation> correlation;
};

/// The case file's [transfer] table as options (command-line flags then override them).
TransferOptions options_from(const TransferSpec& spec);

/// The polynomial an interpolation uses when the user gives none.
RbfPolynomial effective_polynomial(const TransferOptions& options);

/// Memory the dense RBF may use: 3/4 of /proc/meminfo's MemAvailable, capped at 16 GiB.
std::size_t default_dense_memory_limit();

struct TransferResult {
  ParticleCheckpoint particles;
  TransferReport report;
};

/// Transfers one FE checkpoint. Validates what it uses (sizes, finite values, element
/// inversion) and throws Error with a one-line message naming the field, element or
/// option at fault. `logger` receives progress messages (may be null).
TransferResult transfer(const FemCheckpoint& fem, const TransferOptions& options,
                        const Logger* logger = nullptr);

}  // namespace slide::transfer
