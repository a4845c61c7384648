// Radial basis function interpolation of scattered Gauss-point values (docs/method.md §4).
//
// Multiquadric φ(r) = sqrt((r/c)² + 1) with shape parameter c (a length, m). The
// interpolant through the values y_i at the centres x_i is
//     s(x) = Σ_i λ_i φ(|x − x_i|) [+ a_0 + a_x x̂ + a_y ŷ]
// - plain (RbfPolynomial::none, the form of the paper): Φ λ = y, Φ_ij = φ(|x_i − x_j|).
//   Φ is symmetric but indefinite (one positive eigenvalue), so it is factorised by LU
//   with partial pivoting, once, and the factors serve every field component.
// - linear augmentation (RbfPolynomial::linear): the saddle-point system
//     [Φ  P] [λ]   [y]        P_i = [1, x̂_i, ŷ_i]
//     [Pᵀ 0] [a] = [0]        (side conditions Σλ = Σλx = Σλy = 0)
//   reproduces every linear field exactly, also outside the cloud of centres. x̂ are the
//   coordinates shifted and scaled to O(1) for conditioning (the span is unchanged). When
//   the centres are collinear the linear terms are undetermined: the polynomial is then
//   reduced to the constant and the reduction is counted.
// Two variants: `DenseRbf` (one global system, O(N³) time, O(N²) memory) and
// `interpolate_local_rbf` (the same interpolant over the k nearest centres of each
// evaluation point, found with a k-d tree: O(N_p k³), scales to millions of points).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "common/base/types.hpp"
#include "common/physics/algorithms.hpp"

namespace slide::transfer {

/// Values of several field components at a set of points: one row per point, one column
/// per component (stress, strain, state, … packed side by side).
using FieldValues = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The classic default c = sqrt(A_box / N): the mean spacing of N centres spread over
/// their bounding box. A degenerate box (all centres on a line) uses its length / N.
double default_shape_parameter(std::span<const Vec2> centres);

/// What a fit tells about its linear systems.
struct RbfDiagnostics {
  /// Estimate of the 1-norm condition number 1/rcond of the (worst) factorised system.
  double condition_estimate = 0.0;
  /// Systems whose centres were collinear, so that the linear polynomial was reduced to
  /// the constant.
  std::size_t reduced_polynomial = 0;
  /// Factorisations performed (1 for the dense variant).
  std::size_t factorisations = 0;
};

/// Bytes the dense variant needs for its matrix (factorised in place).
std::size_t dense_rbf_bytes(std::size_t centres, RbfPolynomial polynomial);

/// The global interpolant through every centre.
class DenseRbf {
 public:
  /// Builds Φ (augmented when asked), factorises it once and solves for every column of
  /// `values` (rows: centres). Throws Error recommending rbf-local when the matrix
  /// needs more than `memory_limit_bytes`.
  DenseRbf(std::span<const Vec2> centres, const FieldValues& values, double shape,
           RbfPolynomial polynomial, std::size_t memory_limit_bytes);

  /// s(x) of every component at every point, rows in the order of `points`. Parallel
  /// over blocks of points; each value is summed in a fixed order (deterministic).
  FieldValues evaluate(std::span<const Vec2> points) const;

  const RbfDiagnostics& diagnostics() const { return diagnostics_; }
  double shape() const { return shape_; }

 private:
  std::vector<Vec2> centres_;
  double shape_;
  int polynomial_terms_;  // 0, 1 (constant only) or 3
  Vec2 origin_;           // x̂ = (x − origin) / scale
  double scale_;
  FieldValues weights_;     // λ: one row per centre
  FieldValues polynomial_;  // a: one row per polynomial term
  RbfDiagnostics diagnostics_;
};

struct LocalRbfOptions {
  double shape = 1.0;  ///< c, m
  RbfPolynomial polynomial = RbfPolynomial::linear;
  int neighbours = 16;  ///< k (capped at the number of centres)
};

/// Interpolates every column of `values` (rows: centres) at `points`, each from the
/// multiquadric through its k nearest centres. Parallel over points (OpenMP) and
/// deterministic: a neighbourhood is identified by its sorted centre indices, so the
/// same neighbourhood always gives the same coefficients, whichever thread solves it.
FieldValues interpolate_local_rbf(std::span<const Vec2> centres, const FieldValues& values,
                                  std::span<const Vec2> points, const LocalRbfOptions& options,
                                  RbfDiagnostics* diagnostics = nullptr);

}  // namespace slide::transfer
