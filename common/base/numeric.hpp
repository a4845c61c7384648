// Small numeric predicates shared by the layers above (the case reader and the run loop
// must agree on them).
#pragma once

#include <algorithm>
#include <cmath>

namespace slide {

/// Whether `value` is a whole multiple of `step` (> 0), to 1e-9 of the multiple: a
/// cadence written in decimal seconds (0.3 s of 0.1 s steps) is not one exactly in binary.
inline bool is_whole_multiple(double value, double step) {
  const double multiple = value / step;
  return std::abs(multiple - std::round(multiple)) <= 1e-9 * std::max(1.0, multiple);
}

/// Compensated (Neumaier) sum: the conservation totals of the report compare sums over
/// millions of terms to 1e-12, below what naive summation guarantees.
class CompensatedSum {
 public:
  void add(double value) {
    const double t = sum_ + value;
    compensation_ += std::abs(sum_) >= std::abs(value) ? (sum_ - t) + value : (value - t) + sum_;
    sum_ = t;
  }
  double value() const { return sum_ + compensation_; }

 private:
  double sum_ = 0.0;
  double compensation_ = 0.0;
};

}  // namespace slide
