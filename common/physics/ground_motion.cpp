#include "common/physics/ground_motion.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "common/base/error.hpp"

namespace slide {

namespace {

constexpr double pi = std::numbers::pi;

AccelerationRecord sample(double duration, double step, auto&& function) {
  AccelerationRecord record;
  // A wavelet or a sine train is sampled whole: at most 1e8 samples (1.6 GB). A duration
  // of 2^31 s (a fuzzer's mutant) is refused in one line, not allocated.
  constexpr double most_samples = 1e8;
  if (!(duration / step < most_samples)) {
    throw Error(
        "motion: {:g} s sampled every {:g} s would need {:.3g} samples (at most {:g}): shorten "
        "the motion (peak_time, duration)",
        duration, step, duration / step, most_samples);
  }
  const auto n = static_cast<std::size_t>(std::ceil(duration / step - 1e-9)) + 1;
  record.time.reserve(n);
  record.acceleration.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double tau = std::min(static_cast<double>(k) * step, duration);
    record.time.push_back(tau);
    record.acceleration.push_back(function(tau));
  }
  return record;
}

void check_record(const AccelerationRecord& record, std::string_view component) {
  if (record.time.size() != record.acceleration.size()) {
    throw Error("{} motion: {} times but {} accelerations", component, record.time.size(),
                record.acceleration.size());
  }
  for (std::size_t k = 0; k < record.time.size(); ++k) {
    if (!std::isfinite(record.time[k]) || !std::isfinite(record.acceleration[k])) {
      throw Error("{} motion: sample {} is not finite (t = {}, a = {})", component, k,
                  record.time[k], record.acceleration[k]);
    }
    if (k > 0 && !(record.time[k] > record.time[k - 1])) {
      throw Error("{} motion: time {} s of sample {} does not follow {} s", component,
                  record.time[k], k, record.time[k - 1]);
    }
  }
}

/// a(τ_k) of a record by linear interpolation, zero outside it.
double resampled(const AccelerationRecord& record, double tau) {
  const auto& t = record.time;
  if (t.empty() || tau < t.front() || tau > t.back()) return 0.0;
  const auto upper = std::upper_bound(t.begin(), t.end(), tau);
  if (upper == t.end()) return record.acceleration.back();
  const auto i = static_cast<std::size_t>(upper - t.begin());
  if (i == 0) return record.acceleration.front();
  const double w = (tau - t[i - 1]) / (t[i] - t[i - 1]);
  return (1.0 - w) * record.acceleration[i - 1] + w * record.acceleration[i];
}

/// Trapezoidal running integral of `f` (first value 0).
std::vector<double> integrate(const std::vector<double>& f, double step) {
  std::vector<double> integral(f.size(), 0.0);
  for (std::size_t k = 1; k < f.size(); ++k) {
    integral[k] = integral[k - 1] + 0.5 * step * (f[k - 1] + f[k]);
  }
  return integral;
}

/// The final velocity and displacement of the `n` acceleration samples f(k) under the
/// trapezoidal rule, streamed (the samples are not stored: a record may be far longer
/// than the part of it a run keeps).
std::pair<double, double> end_values(std::size_t n, double step, auto&& f) {
  double a = f(std::size_t{0}), v = 0.0, u = 0.0;
  for (std::size_t k = 1; k < n; ++k) {
    const double a_next = f(k);
    const double v_next = v + 0.5 * step * (a + a_next);
    u += 0.5 * step * (v + v_next);
    a = a_next;
    v = v_next;
  }
  return {v, u};
}

/// The linear function c0 + c1 τ whose subtraction from the `n` samples f(k) makes the
/// discrete v and u end at zero (zero for fewer than 3 samples or a singular system).
std::pair<double, double> baseline(std::size_t n, double step, auto&& f) {
  if (n < 3) return {0.0, 0.0};
  const auto ramp = [step](std::size_t k) { return static_cast<double>(k) * step; };
  const auto [v, u] = end_values(n, step, f);
  const auto [v0, u0] = end_values(n, step, [](std::size_t) { return 1.0; });
  const auto [v1, u1] = end_values(n, step, ramp);
  // [v0 v1; u0 u1] [c0; c1] = [v; u]
  const double det = v0 * u1 - v1 * u0;
  if (!(std::abs(det) > 0.0)) return {0.0, 0.0};
  return {(v * u1 - v1 * u) / det, (v0 * u - v * u0) / det};
}

}  // namespace

AccelerationRecord ricker_wavelet(double amplitude, double peak_frequency, double peak_time,
                                  double step) {
  const double b = pi * pi * peak_frequency * peak_frequency;
  return sample(2.0 * peak_time, step, [&](double tau) {
    const double s = tau - peak_time;
    return amplitude * (1.0 - 2.0 * b * s * s) * std::exp(-b * s * s);
  });
}

AccelerationRecord sine_train(double amplitude, double frequency, double duration, double taper,
                              double step) {
  return sample(duration, step, [&](double tau) {
    double w = 1.0;
    const double from_end = std::min(tau, duration - tau);
    if (taper > 0.0 && from_end < taper) w = 0.5 * (1.0 - std::cos(pi * from_end / taper));
    return amplitude * w * std::sin(2.0 * pi * frequency * tau);
  });
}

GroundMotion::GroundMotion(const AccelerationRecord& horizontal, const AccelerationRecord& vertical,
                           double start_time, double step, bool baseline_correction,
                           double keep_until)
    : start_time_(start_time), step_(step), has_vertical_(!vertical.time.empty()) {
  check_record(horizontal, "horizontal");
  check_record(vertical, "vertical");
  if (!(step > 0.0) || !std::isfinite(step)) throw Error("motion: sampling step {} s", step);
  double duration = 0.0;
  for (const auto* record : {&horizontal, &vertical}) {
    if (!record->time.empty()) duration = std::max(duration, record->time.back());
  }
  // The whole record is resampled (and corrected) by streaming; only the samples up to
  // keep_until, and one after it, are stored.
  const double samples = std::ceil(duration / step - 1e-9) + 1.0;
  if (samples > max_record_samples) {
    throw Error("motion: {} s sampled every {} s is {:.3g} samples (at most {:.0e})", duration,
                step, samples, max_record_samples);
  }
  const auto n = static_cast<std::size_t>(samples);
  record_end_time_ = start_time + static_cast<double>(n - 1) * step;
  std::size_t kept = n;
  if (keep_until < record_end_time_) {
    const double until = std::ceil((keep_until - start_time) / step - 1e-9) + 2.0;
    kept = std::min(n, static_cast<std::size_t>(std::max(until, 2.0)));
  }
  std::array<std::vector<double>, 2> a;
  for (int c = 0; c < 2; ++c) {
    const AccelerationRecord& record = c == 0 ? horizontal : vertical;
    const auto f = [&](std::size_t k) { return resampled(record, static_cast<double>(k) * step); };
    a[c].resize(kept);
    for (std::size_t k = 0; k < kept; ++k) a[c][k] = f(k);
    if (!baseline_correction) continue;
    const auto [c0, c1] = baseline(n, step, f);
    for (std::size_t k = 0; k < kept; ++k) a[c][k] -= c0 + c1 * (static_cast<double>(k) * step);
    correction_start_[c] = c0;
    correction_end_[c] = c0 + c1 * (static_cast<double>(n - 1) * step);
  }
  const std::array<std::vector<double>, 2> v{integrate(a[0], step), integrate(a[1], step)};
  const std::array<std::vector<double>, 2> u{integrate(v[0], step), integrate(v[1], step)};
  acceleration_.resize(kept);
  velocity_.resize(kept);
  displacement_.resize(kept);
  for (std::size_t k = 0; k < kept; ++k) {
    acceleration_[k] = {a[0][k], a[1][k]};
    velocity_[k] = {v[0][k], v[1][k]};
    displacement_[k] = {u[0][k], u[1][k]};
  }
}

GroundMotion::GroundMotion(double start_time, double step, std::vector<Vec2> acceleration,
                           std::vector<Vec2> velocity, std::vector<Vec2> displacement,
                           double record_end_time)
    : start_time_(start_time),
      step_(step),
      acceleration_(std::move(acceleration)),
      velocity_(std::move(velocity)),
      displacement_(std::move(displacement)) {
  if (!(step > 0.0) || !std::isfinite(step_) || !std::isfinite(start_time_)) {
    throw Error("motion: start time {} s, sampling step {} s", start_time, step);
  }
  if (velocity_.size() != acceleration_.size() || displacement_.size() != acceleration_.size()) {
    throw Error("motion: {} accelerations, {} velocities, {} displacements", acceleration_.size(),
                velocity_.size(), displacement_.size());
  }
  has_vertical_ = std::ranges::any_of(acceleration_, [](const Vec2& a) { return a.y() != 0.0; });
  record_end_time_ =
      std::isnan(record_end_time) ? end_time() : std::max(record_end_time, end_time());
}

double GroundMotion::end_time() const {
  return start_time_ +
         step_ * static_cast<double>(acceleration_.empty() ? 0 : acceleration_.size() - 1);
}

Vec2 GroundMotion::interpolate(const std::vector<Vec2>& samples, double t,
                               const Vec2& after) const {
  if (samples.empty()) return Vec2::Zero();
  const double s = (t - start_time_) / step_;
  if (!(s > 0.0)) return s == 0.0 ? samples.front() : Vec2::Zero();
  const double last = static_cast<double>(samples.size() - 1);
  if (s >= last) return s == last ? samples.back() : after;
  const auto k = static_cast<std::size_t>(s);
  const double w = s - static_cast<double>(k);
  return (1.0 - w) * samples[k] + w * samples[k + 1];
}

Vec2 GroundMotion::displacement(double t) const {
  if (displacement_.empty()) return Vec2::Zero();
  const double s = (t - start_time_) / step_;
  const double last = static_cast<double>(displacement_.size() - 1);
  if (!(s > 0.0) || s >= last) {
    return interpolate(displacement_, t, displacement_.back());
  }
  // Cubic Hermite on (u, v) at the two samples: the displacement is C¹ and its slope the
  // sampled velocity, so the velocity of a step shorter than the sampling step is that
  // of its own instant, not the mean of the sampling interval it falls in.
  const auto k = static_cast<std::size_t>(s);
  const double w = s - static_cast<double>(k);
  const double w2 = w * w, w3 = w2 * w;
  return (2.0 * w3 - 3.0 * w2 + 1.0) * displacement_[k] +
         (w3 - 2.0 * w2 + w) * step_ * velocity_[k] +
         (-2.0 * w3 + 3.0 * w2) * displacement_[k + 1] + (w3 - w2) * step_ * velocity_[k + 1];
}
Vec2 GroundMotion::velocity(double t) const {
  return interpolate(velocity_, t, Vec2::Zero());
}
Vec2 GroundMotion::acceleration(double t) const {
  return interpolate(acceleration_, t, Vec2::Zero());
}

Vec2 GroundMotion::step_velocity(double t, double dt) const {
  return (displacement(t + dt) - displacement(t)) / dt;
}

GroundMotion::Peaks GroundMotion::peaks() const {
  Peaks peaks;
  for (std::size_t k = 0; k < acceleration_.size(); ++k) {
    peaks.acceleration = peaks.acceleration.cwiseMax(acceleration_[k].cwiseAbs());
    peaks.velocity = peaks.velocity.cwiseMax(velocity_[k].cwiseAbs());
    peaks.displacement = peaks.displacement.cwiseMax(displacement_[k].cwiseAbs());
  }
  return peaks;
}

std::string motion_csv(const GroundMotion& motion) {
  std::string text = "time,ax,vx,ux,ay,vy,uy\n";
  const auto& a = motion.acceleration_samples();
  const auto& v = motion.velocity_samples();
  const auto& u = motion.displacement_samples();
  for (std::size_t k = 0; k < a.size(); ++k) {
    text += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n",
                        motion.start_time() + static_cast<double>(k) * motion.step(), a[k].x(),
                        v[k].x(), u[k].x(), a[k].y(), v[k].y(), u[k].y());
  }
  return text;
}

}  // namespace slide
