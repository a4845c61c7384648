#include "transfer/rbf_interpolation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/LU>
#include <nanoflann.hpp>

#include "common/base/error.hpp"

namespace slide::transfer {

namespace {

/// Frame of the polynomial part: x̂ = (x − origin)/scale keeps the columns of P of order
/// one whatever the units and position of the model, and the number of terms kept.
struct PolynomialFrame {
  Vec2 origin = Vec2::Zero();
  double scale = 1.0;
  int terms = 0;
};

/// Relative smallest extent below which the centres count as collinear.
constexpr double collinear_tolerance = 1e-10;

template <typename PointOf>
PolynomialFrame polynomial_frame(std::size_t count, const PointOf& point_of,
                                 RbfPolynomial polynomial) {
  PolynomialFrame frame;
  if (polynomial == RbfPolynomial::none || count == 0) return frame;
  for (std::size_t i = 0; i < count; ++i) frame.origin += point_of(i);
  frame.origin /= static_cast<double>(count);
  double radius = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    radius = std::max(radius, (point_of(i) - frame.origin).norm());
  }
  frame.scale = radius > 0.0 ? radius : 1.0;
  // The linear terms are determined only when the centres span the plane: the second
  // moment (covariance) of x̂ must have two non-negligible eigenvalues.
  Mat2 moment = Mat2::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Vec2 x = (point_of(i) - frame.origin) / frame.scale;
    moment += x * x.transpose();
  }
  const double trace = moment.trace();
  const double det = moment.determinant();
  const double discriminant = std::sqrt(std::max(0.0, 0.25 * trace * trace - det));
  const double largest = 0.5 * trace + discriminant;
  const double smallest = 0.5 * trace - discriminant;
  frame.terms = count >= 3 && smallest > collinear_tolerance * largest ? 3 : 1;
  return frame;
}

/// [1, x̂, ŷ] truncated to the frame's terms.
inline void polynomial_row(const PolynomialFrame& frame, const Vec2& x, double* row) {
  row[0] = 1.0;
  if (frame.terms == 3) {
    const Vec2 scaled = (x - frame.origin) / frame.scale;
    row[1] = scaled.x();
    row[2] = scaled.y();
  }
}

/// φ(r) = sqrt((r/c)² + 1) from r² and 1/c².
inline double multiquadric(double r_squared, double inverse_c_squared) {
  return std::sqrt(r_squared * inverse_c_squared + 1.0);
}

// ---------------------------------------------------------------- k-d tree adaptor

struct CentreCloud {
  std::span<const Vec2> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return points[i][static_cast<Eigen::Index>(dim)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CentreCloud>,
                                        CentreCloud, 2, std::uint32_t>;

}  // namespace

double default_shape_parameter(std::span<const Vec2> centres) {
  if (centres.empty()) return 1.0;
  Vec2 low = centres.front(), high = centres.front();
  for (const auto& x : centres) {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  const Vec2 extent = high - low;
  const auto n = static_cast<double>(centres.size());
  const double area = extent.x() * extent.y();
  const double length = extent.maxCoeff();
  // A line of centres has no area: its mean spacing is its length over the count.
  if (area > 1e-12 * length * length && area > 0.0) return std::sqrt(area / n);
  if (length > 0.0) return length / n;
  return 1.0;
}

std::size_t dense_rbf_bytes(std::size_t centres, RbfPolynomial polynomial) {
  const std::size_t n = centres + (polynomial == RbfPolynomial::linear ? 3 : 0);
  return n * n * sizeof(double);
}

// ---------------------------------------------------------------- dense

DenseRbf::DenseRbf(std::span<const Vec2> centres, const FieldValues& values, double shape,
                   RbfPolynomial polynomial, std::size_t memory_limit_bytes)
    : centres_(centres.begin(), centres.end()), shape_(shape) {
  const auto n = static_cast<Eigen::Index>(centres.size());
  if (n == 0) throw Error("rbf: no Gauss points to interpolate from");
  if (values.rows() != n) {
    throw Error("rbf: {} values for {} Gauss points", values.rows(), n);
  }
  if (!(shape > 0.0) || !std::isfinite(shape)) {
    throw Error("rbf: shape parameter c = {} is not admissible (expected > 0 m)", shape);
  }
  const std::size_t bytes = dense_rbf_bytes(centres.size(), polynomial);
  if (bytes > memory_limit_bytes) {
    throw Error(
        "rbf: the dense {}×{} multiquadric matrix of {} Gauss points needs {:.1f} GiB, more "
        "than the {:.1f} GiB allowed; use --stress-interpolation rbf-local",
        n, n, n, static_cast<double>(bytes) / (1 << 30),
        static_cast<double>(memory_limit_bytes) / (1 << 30));
  }

  const PolynomialFrame frame = polynomial_frame(
      centres.size(), [&](std::size_t i) -> const Vec2& { return centres[i]; }, polynomial);
  origin_ = frame.origin;
  scale_ = frame.scale;
  polynomial_terms_ = frame.terms;
  if (polynomial == RbfPolynomial::linear && frame.terms < 3) diagnostics_.reduced_polynomial = 1;
  const Eigen::Index m = n + polynomial_terms_;

  // Φ and, augmented, the blocks P and Pᵀ. Filled column by column in parallel: each
  // entry is written by one thread, so the matrix is the same for any thread count.
  Eigen::MatrixXd matrix(m, m);
  const double inverse_c_squared = 1.0 / (shape * shape);
#pragma omp parallel for schedule(static)
  for (Eigen::Index j = 0; j < n; ++j) {
    const Vec2& xj = centres[static_cast<std::size_t>(j)];
    for (Eigen::Index i = 0; i < n; ++i) {
      matrix(i, j) = multiquadric((centres[static_cast<std::size_t>(i)] - xj).squaredNorm(),
                                  inverse_c_squared);
    }
  }
  if (polynomial_terms_ > 0) {
    std::array<double, 3> row{};
    for (Eigen::Index i = 0; i < n; ++i) {
      polynomial_row(frame, centres[static_cast<std::size_t>(i)], row.data());
      for (int t = 0; t < polynomial_terms_; ++t) {
        matrix(i, n + t) = row[static_cast<std::size_t>(t)];
        matrix(n + t, i) = row[static_cast<std::size_t>(t)];
      }
    }
    matrix.bottomRightCorner(polynomial_terms_, polynomial_terms_).setZero();
  }

  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, values.cols());
  rhs.topRows(n) = values;

  // One in-place factorisation, every component solved with it.
  Eigen::PartialPivLU<Eigen::Ref<Eigen::MatrixXd>> lu(matrix);
  const double rcond = lu.rcond();
  diagnostics_.condition_estimate =
      rcond > 0.0 ? 1.0 / rcond : std::numeric_limits<double>::infinity();
  diagnostics_.factorisations = 1;
  const Eigen::MatrixXd solution = lu.solve(rhs);
  if (!solution.allFinite()) {
    throw Error(
        "rbf: the multiquadric system is singular (duplicate Gauss points?); condition "
        "estimate {:.3g}",
        diagnostics_.condition_estimate);
  }
  weights_ = solution.topRows(n);
  polynomial_ = solution.bottomRows(polynomial_terms_);
}

FieldValues DenseRbf::evaluate(std::span<const Vec2> points) const {
  const auto n = static_cast<Eigen::Index>(centres_.size());
  const Eigen::Index components = weights_.cols();
  const auto count = static_cast<Eigen::Index>(points.size());
  FieldValues result(count, components);
  // Blocks of points: Φ_block (points × centres) times λ is a matrix product, which Eigen
  // vectorises; a block holds about 8 MB of Φ.
  const Eigen::Index block =
      std::clamp<Eigen::Index>((Eigen::Index{1} << 20) / std::max<Eigen::Index>(n, 1), 8, 256);
  const Eigen::Index blocks = (count + block - 1) / block;
  const double inverse_c_squared = 1.0 / (shape_ * shape_);
  const PolynomialFrame frame{origin_, scale_, polynomial_terms_};
#pragma omp parallel
  {
    Eigen::MatrixXd phi(block, n);
    Eigen::MatrixXd p(block, std::max(polynomial_terms_, 1));
#pragma omp for schedule(static)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      const Eigen::Index first = b * block;
      const Eigen::Index rows = std::min(block, count - first);
      for (Eigen::Index r = 0; r < rows; ++r) {
        const Vec2& x = points[static_cast<std::size_t>(first + r)];
        for (Eigen::Index i = 0; i < n; ++i) {
          phi(r, i) = multiquadric((centres_[static_cast<std::size_t>(i)] - x).squaredNorm(),
                                   inverse_c_squared);
        }
        if (polynomial_terms_ > 0) {
          std::array<double, 3> row{};
          polynomial_row(frame, x, row.data());
          for (int t = 0; t < polynomial_terms_; ++t) p(r, t) = row[static_cast<std::size_t>(t)];
        }
      }
      auto out = result.middleRows(first, rows);
      out.noalias() = phi.topRows(rows) * weights_;
      if (polynomial_terms_ > 0) {
        out.noalias() += p.topLeftCorner(rows, polynomial_terms_) * polynomial_;
      }
    }
  }
  return result;
}

// ---------------------------------------------------------------- local

namespace {

void check_local_inputs(std::span<const Vec2> centres, const FieldValues& values,
                        const LocalRbfOptions& options) {
  if (centres.empty()) throw Error("rbf-local: no Gauss points to interpolate from");
  if (values.rows() != static_cast<Eigen::Index>(centres.size())) {
    throw Error("rbf-local: {} values for {} Gauss points", values.rows(), centres.size());
  }
  if (centres.size() >= std::numeric_limits<std::uint32_t>::max()) {
    throw Error("rbf-local: {} Gauss points exceed the k-d tree's index range", centres.size());
  }
  if (!(options.shape > 0.0) || !std::isfinite(options.shape)) {
    throw Error("rbf-local: shape parameter c = {} is not admissible (expected > 0 m)",
                options.shape);
  }
  if (options.neighbours < 1) {
    throw Error("rbf-local: {} neighbours is not admissible (expected ≥ 1)", options.neighbours);
  }
}

/// One thread's interpolant through its current neighbourhood; the buffers are reused
/// from point to point, so a thread allocates only when a neighbourhood grows.
struct NeighbourhoodFit {
  Eigen::MatrixXd matrix, rhs, coefficients;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  PolynomialFrame frame;
};

/// Solves the (augmented) multiquadric system through the centres `neighbours` for every
/// column of `values`; returns its condition estimate 1/rcond.
double fit_neighbourhood(std::span<const Vec2> centres, const FieldValues& values,
                         const std::vector<std::uint32_t>& neighbours, RbfPolynomial polynomial,
                         double inverse_c_squared, NeighbourhoodFit& fit) {
  const auto nk = static_cast<Eigen::Index>(neighbours.size());
  auto centre = [&](std::size_t i) -> const Vec2& { return centres[neighbours[i]]; };
  fit.frame = polynomial_frame(neighbours.size(), centre, polynomial);
  const Eigen::Index m = nk + fit.frame.terms;
  fit.matrix.resize(m, m);
  fit.rhs.setZero(m, values.cols());
  std::array<double, 3> row{};
  for (Eigen::Index j = 0; j < nk; ++j) {
    const Vec2& xj = centre(static_cast<std::size_t>(j));
    for (Eigen::Index i = 0; i < nk; ++i) {
      fit.matrix(i, j) =
          multiquadric((centre(static_cast<std::size_t>(i)) - xj).squaredNorm(), inverse_c_squared);
    }
    polynomial_row(fit.frame, xj, row.data());
    for (int t = 0; t < fit.frame.terms; ++t) {
      fit.matrix(j, nk + t) = row[static_cast<std::size_t>(t)];
      fit.matrix(nk + t, j) = row[static_cast<std::size_t>(t)];
    }
    fit.rhs.row(j) = values.row(static_cast<Eigen::Index>(neighbours[static_cast<std::size_t>(j)]));
  }
  fit.matrix.bottomRightCorner(fit.frame.terms, fit.frame.terms).setZero();
  fit.lu.compute(fit.matrix);
  const double rcond = fit.lu.rcond();
  fit.coefficients = fit.lu.solve(fit.rhs);
  return rcond > 0.0 ? 1.0 / rcond : std::numeric_limits<double>::infinity();
}

/// s(x) = Σ_j λ_j φ(|x − x_j|) + a·[1, x̂, ŷ] of the fitted neighbourhood, into `out`.
void evaluate_neighbourhood(std::span<const Vec2> centres,
                            const std::vector<std::uint32_t>& neighbours,
                            const NeighbourhoodFit& fit, double inverse_c_squared, const Vec2& x,
                            FieldValues::RowXpr out) {
  out.setZero();
  const auto nk = static_cast<Eigen::Index>(neighbours.size());
  for (Eigen::Index j = 0; j < nk; ++j) {
    const double phi = multiquadric(
        (centres[neighbours[static_cast<std::size_t>(j)]] - x).squaredNorm(), inverse_c_squared);
    out += phi * fit.coefficients.row(j);
  }
  std::array<double, 3> row{};
  polynomial_row(fit.frame, x, row.data());
  for (int t = 0; t < fit.frame.terms; ++t) {
    out += row[static_cast<std::size_t>(t)] * fit.coefficients.row(nk + t);
  }
}

}  // namespace

FieldValues interpolate_local_rbf(std::span<const Vec2> centres, const FieldValues& values,
                                  std::span<const Vec2> points, const LocalRbfOptions& options,
                                  RbfDiagnostics* diagnostics) {
  check_local_inputs(centres, values, options);
  const CentreCloud cloud{centres};
  const KdTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  const auto k = static_cast<std::size_t>(
      std::min<std::size_t>(static_cast<std::size_t>(options.neighbours), centres.size()));
  const double inverse_c_squared = 1.0 / (options.shape * options.shape);
  const auto count = static_cast<std::ptrdiff_t>(points.size());
  FieldValues result(static_cast<Eigen::Index>(points.size()), values.cols());

  double worst_condition = 0.0;
  std::size_t reduced = 0, factorisations = 0;
#pragma omp parallel reduction(max : worst_condition) reduction(+ : reduced, factorisations)
  {
    std::vector<std::uint32_t> found(k), neighbours, cached;
    std::vector<double> distances(k);
    NeighbourhoodFit fit;
#pragma omp for schedule(static)
    for (std::ptrdiff_t p = 0; p < count; ++p) {
      const Vec2& x = points[static_cast<std::size_t>(p)];
      const double query[2] = {x.x(), x.y()};
      const std::size_t got = tree.knnSearch(query, k, found.data(), distances.data());
      neighbours.assign(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(got));
      // The system depends on the neighbourhood as a set: order it by index so that the
      // same set always gives bit-identical coefficients (ties in distance may come back
      // in any order), and reuse the last solution when the set has not changed (the
      // particles of one element mostly share their neighbourhood).
      std::sort(neighbours.begin(), neighbours.end());
      if (neighbours != cached) {
        worst_condition = std::max(
            worst_condition, fit_neighbourhood(centres, values, neighbours, options.polynomial,
                                               inverse_c_squared, fit));
        if (options.polynomial == RbfPolynomial::linear && fit.frame.terms < 3) ++reduced;
        ++factorisations;
        cached = neighbours;
      }
      evaluate_neighbourhood(centres, neighbours, fit, inverse_c_squared, x,
                             result.row(static_cast<Eigen::Index>(p)));
    }
  }
  if (!result.allFinite()) {
    throw Error("rbf-local: a neighbourhood system is singular (duplicate Gauss points?)");
  }
  if (diagnostics != nullptr) {
    diagnostics->condition_estimate = worst_condition;
    diagnostics->reduced_polynomial = reduced;
    diagnostics->factorisations = factorisations;
  }
  return result;
}

}  // namespace slide::transfer
