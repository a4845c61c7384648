// The input motion of a seismic run (docs/method.md §8): the base acceleration a_g(t),
// horizontal and optionally vertical, processed once into uniform samples of
// acceleration, velocity and displacement that both phases evaluate.
//
// Processing, in order:
//   1. the raw acceleration (a record's samples, a Ricker wavelet, a tapered sine train)
//      is resampled by linear interpolation onto a uniform step (the solver's step);
//   2. integrated by the trapezoidal rule: v_k = v_{k−1} + (a_{k−1} + a_k) Δτ/2, and u
//      likewise from v;
//   3. baseline correction: a linear function c0 + c1 τ is subtracted from the
//      acceleration, its two coefficients chosen so that the *discrete* velocity and
//      displacement of step 2 end at exactly zero (a 2 × 2 solve with the integrals of 1
//      and τ under the same rule), so that the base ends where it started and at rest.
// τ = t − start_time is the motion's own clock; t is the clock of the run (t = 0 at the
// start of the failure stage). Before τ = 0 and after the last sample the base is at
// rest at its start and end positions (the latter zero after correction).
//
// A prescribed base moves by whole displacement increments: over a step t → t + dt its
// velocity is (u_g(t + dt) − u_g(t))/dt (step_velocity), so the base of the leapfrog
// scheme is at u_g(t) at every step, whatever the step.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "common/base/types.hpp"

namespace slide {

/// Raw acceleration samples of one component: times τ (s, from 0, increasing) and a (m/s²).
struct AccelerationRecord {
  std::vector<double> time;
  std::vector<double> acceleration;
};

/// a(τ) = A (1 − 2 π² f² (τ − τ_p)²) exp(−π² f² (τ − τ_p)²) on [0, 2 τ_p], sampled at Δτ.
AccelerationRecord ricker_wavelet(double amplitude, double peak_frequency, double peak_time,
                                  double step);

/// a(τ) = A w(τ) sin(2π f τ) on [0, D], w a cosine (Tukey) taper rising over the first
/// `taper` seconds and falling over the last (1 in between), sampled at Δτ.
AccelerationRecord sine_train(double amplitude, double frequency, double duration, double taper,
                              double step);

/// The processed motion: uniform samples of both components (zero where a component is
/// absent), on the motion's clock τ_k = k Δτ.
class GroundMotion {
 public:
  GroundMotion() = default;
  /// Resamples `horizontal` and `vertical` (either may be empty: no motion in that
  /// direction) onto Δτ = `step`, integrates and, when `baseline_correction`, corrects
  /// them over the whole record; keeps the samples up to the run's time `keep_until` (and
  /// one after it): what is stored, checkpointed and written is bounded by the runs, not
  /// by the record. Throws Error when a record is not increasing or not finite, or longer
  /// than max_record_samples steps.
  GroundMotion(const AccelerationRecord& horizontal, const AccelerationRecord& vertical,
               double start_time, double step, bool baseline_correction,
               double keep_until = std::numeric_limits<double>::infinity());
  /// From samples already processed (a checkpoint's /motion group); `record_end_time`,
  /// when the samples stop before the record did (NaN: where the samples end).
  GroundMotion(double start_time, double step, std::vector<Vec2> acceleration,
               std::vector<Vec2> velocity, std::vector<Vec2> displacement,
               double record_end_time = std::numeric_limits<double>::quiet_NaN());

  /// The longest record processed, in samples of the solver's step: 5e8 (two passes over
  /// it take seconds; only the run's part is stored).
  static constexpr double max_record_samples = 5e8;

  bool empty() const { return acceleration_.empty(); }
  double start_time() const { return start_time_; }
  double step() const { return step_; }
  /// The run's time of the last sample.
  double end_time() const;
  /// The run's time where the record ends: end_time(), or later when the samples were
  /// kept only up to the end of the runs.
  double record_end_time() const { return record_end_time_; }
  /// The samples stop before the record does (the base would rest after end_time()).
  bool cut() const { return record_end_time_ > end_time() + 0.5 * step_; }
  bool has_vertical() const { return has_vertical_; }

  /// Base displacement, velocity and acceleration at the run's time t (at rest outside
  /// the motion): the displacement by cubic Hermite interpolation of the sampled u and
  /// v, the others linearly between samples.
  Vec2 displacement(double t) const;
  Vec2 velocity(double t) const;
  Vec2 acceleration(double t) const;
  /// The base velocity over the step t → t + dt: (u_g(t + dt) − u_g(t))/dt.
  Vec2 step_velocity(double t, double dt) const;

  /// The largest |a|, |v| and |u| of each component over the motion.
  struct Peaks {
    Vec2 acceleration = Vec2::Zero();
    Vec2 velocity = Vec2::Zero();
    Vec2 displacement = Vec2::Zero();
  };
  Peaks peaks() const;
  /// The acceleration that baseline correction subtracted at τ = 0 and at the end (what
  /// the log reports, so a user can judge whether the record needed it).
  const Vec2& correction_start() const { return correction_start_; }
  const Vec2& correction_end() const { return correction_end_; }

  const std::vector<Vec2>& acceleration_samples() const { return acceleration_; }
  const std::vector<Vec2>& velocity_samples() const { return velocity_; }
  const std::vector<Vec2>& displacement_samples() const { return displacement_; }

 private:
  Vec2 interpolate(const std::vector<Vec2>& samples, double t, const Vec2& after) const;

  double start_time_ = 0.0;
  double step_ = 1.0;
  double record_end_time_ = 0.0;
  bool has_vertical_ = false;
  std::vector<Vec2> acceleration_, velocity_, displacement_;
  Vec2 correction_start_ = Vec2::Zero();
  Vec2 correction_end_ = Vec2::Zero();
};

/// The processed motion as CSV (time on the run's clock, then a, v, u of x and of y).
std::string motion_csv(const GroundMotion& motion);

}  // namespace slide
