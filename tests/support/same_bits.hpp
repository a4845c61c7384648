// Two-lane code (common/base/pair.hpp) against its scalar twin: each lane does the scalar
// operations in their order, so the bits are the same, except where the build contracts
// products and sums into FMAs (-march=native), which it may decide differently in the
// two copies: there the values agree within `fused_tolerance`.
#pragma once

#include <gtest/gtest.h>

namespace slide::testing {

inline void expect_same_bits(double from_pair, double from_scalar, double fused_tolerance) {
#ifdef __FMA__
  EXPECT_NEAR(from_pair, from_scalar, fused_tolerance);
#else
  (void)fused_tolerance;
  EXPECT_EQ(from_pair, from_scalar);
#endif
}

}  // namespace slide::testing
