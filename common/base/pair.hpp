// Two doubles that load, compute and store together: the x and y of a node's or a
// particle's vector, or of the particle's two axes (the MPM kernels), two multi-yield
// components (common/physics/multi_yield.cpp), in one SSE2 register (every x86-64 has
// one; GCC's vector extension, a scalar operand is broadcast). Each lane does the IEEE
// operations a scalar line for x or for y would, in the same order, so a pair changes no
// result by itself; the kernels' arithmetic and memory traffic take half the instructions.
// (A build that contracts products and sums into FMAs, -march=native, decides per inlined
// copy which to fuse: there a pair and its scalar twin may differ by an ulp, so each
// quantity is computed by one path only.)
//
// The functions in `lanes` are the <algorithm> ones the shape functions use, for a double
// (std::min, std::max, std::clamp themselves) and for a pair lane by lane with the same
// comparisons, so that code templated on the number type gives the same bits either way.
#pragma once

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace slide {

using Pair = double __attribute__((vector_size(16)));
/// What a comparison of pairs gives: per lane all bits set where it holds, 0 where not.
using Mask = std::int64_t __attribute__((vector_size(16)));

inline Pair load_pair(const double* from) {
  Pair v;
  std::memcpy(&v, from, sizeof v);
  return v;
}
inline void store_pair(double* to, Pair v) {
  std::memcpy(to, &v, sizeof v);
}
/// *to += v for the pair at `to`.
inline void add_pair(double* to, Pair v) {
  store_pair(to, load_pair(to) + v);
}
/// The IEEE square root of each lane, as std::sqrt gives it (one instruction with SSE2).
inline Pair sqrt_pair(Pair v) {
#ifdef __SSE2__
  return _mm_sqrt_pd(v);
#else
  return Pair{std::sqrt(v[0]), std::sqrt(v[1])};
#endif
}

namespace lanes {

inline double min(double a, double b) {
  return std::min(a, b);
}
inline double max(double a, double b) {
  return std::max(a, b);
}
inline double clamp(double v, double lo, double hi) {
  return std::clamp(v, lo, hi);
}
/// std::min's comparison per lane: b < a ? b : a.
inline Pair min(Pair a, Pair b) {
  return b < a ? b : a;
}
/// std::max's: a < b ? b : a.
inline Pair max(Pair a, Pair b) {
  return a < b ? b : a;
}
/// std::abs per lane (the sign bit cleared).
inline Pair abs(Pair v) {
  return Pair{std::abs(v[0]), std::abs(v[1])};
}
/// Whether a lane-by-lane comparison (a mask: all bits set where it holds) holds in both.
inline bool all(Mask m) {
#ifdef __SSE2__
  return _mm_movemask_pd(std::bit_cast<Pair>(m)) == 3;  // the lanes' sign bits
#else
  return m[0] != 0 && m[1] != 0;
#endif
}
/// std::isfinite of both lanes: x − x is 0 for a finite x, NaN for ±∞ and NaN.
inline bool all_finite(Pair v) {
  return all(v - v == 0.0);
}
/// std::clamp's (libstdc++): min(max(v, lo), hi).
inline Pair clamp(Pair v, Pair lo, Pair hi) {
  return min(max(v, lo), hi);
}

}  // namespace lanes
}  // namespace slide
