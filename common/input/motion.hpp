// The processed input motion of a case (docs/method.md §8): [fem.motion] turned into the
// GroundMotion both phases evaluate (common/physics/ground_motion.hpp).
#pragma once

#include "common/physics/ground_motion.hpp"
#include "common/settings/fem_spec.hpp"

namespace slide {

/// The raw acceleration of one component, sampled at `step` where it is built in.
AccelerationRecord raw_acceleration(const MotionComponentSpec& spec, double step);

/// Reads or builds both components, resamples them to `step` (the solver's step),
/// integrates and baseline-corrects them, keeping the samples up to the run's time
/// `keep_until` (the last end time of the runs that use them). Throws Error naming the
/// fault.
GroundMotion make_ground_motion(const MotionSpec& spec, double step, double keep_until);

}  // namespace slide
