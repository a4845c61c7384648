// Checks on Eigen vectors and matrices that the tests share.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace slide::testing {

/// Largest |entry| by a plain loop (Eigen's vectorised reductions trip a false
/// -Wmaybe-uninitialized of GCC 12 with AVX-512).
template <typename Matrix>
double max_abs(const Matrix& m) {
  double largest = 0.0;
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) largest = std::max(largest, std::abs(m(i, j)));
  }
  return largest;
}

}  // namespace slide::testing
