#include "common/input/motion.hpp"

#include "common/io/motion_file.hpp"

namespace slide {

AccelerationRecord raw_acceleration(const MotionComponentSpec& spec, double step) {
  switch (spec.source) {
    case MotionSource::ricker:
      return ricker_wavelet(spec.amplitude, spec.peak_frequency, spec.peak_time, step);
    case MotionSource::sine:
      return sine_train(spec.amplitude, spec.frequency, spec.duration, spec.taper, step);
    case MotionSource::file:
      return read_motion_file(spec.file, spec.scale);
  }
  return {};
}

GroundMotion make_ground_motion(const MotionSpec& spec, double step, double keep_until) {
  const AccelerationRecord horizontal =
      spec.horizontal ? raw_acceleration(*spec.horizontal, step) : AccelerationRecord{};
  const AccelerationRecord vertical =
      spec.vertical ? raw_acceleration(*spec.vertical, step) : AccelerationRecord{};
  return GroundMotion(horizontal, vertical, spec.start_time, step, spec.baseline_correction,
                      keep_until);
}

}  // namespace slide
