// The input motion (common/physics/ground_motion.hpp, common/io/motion_file.hpp) and the
// case reader's [fem.motion] and [[fem.recorders]] (docs/method.md §8).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/input/case_file.hpp"
#include "common/input/motion.hpp"
#include "common/io/motion_file.hpp"
#include "common/physics/ground_motion.hpp"

namespace slide {
namespace {

constexpr double pi = std::numbers::pi;

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// The Ricker wavelet is the second derivative of a Gaussian: its velocity
// v = A (τ − τ_p) exp(−π²f²(τ − τ_p)²) and displacement end at zero by themselves, so
// the baseline correction removes almost nothing and the integrals are the closed form.
TEST(GroundMotion, RickerIntegratesToItsClosedFormVelocity) {
  const double amplitude = 2.0, f = 5.0, tp = 0.3, step = 1e-4;
  const GroundMotion motion(ricker_wavelet(amplitude, f, tp, step), {}, 1.0, step, true);
  const double b = pi * pi * f * f;
  double worst = 0.0;
  for (double tau = 0.0; tau <= 2 * tp; tau += 0.01) {
    const double v = amplitude * (tau - tp) * std::exp(-b * (tau - tp) * (tau - tp));
    worst = std::max(worst, std::abs(motion.velocity(1.0 + tau).x() - v));
  }
  const double peak = amplitude * std::exp(-0.5) / std::sqrt(2 * b);  // |v| at τ − τ_p = ±1/√(2b)
  EXPECT_LT(worst, 1e-6 * peak);
  EXPECT_NEAR(motion.peaks().velocity.x(), peak, 1e-6 * peak);
  EXPECT_NEAR(motion.peaks().acceleration.x(), amplitude, 1e-9);
  EXPECT_LT(std::abs(motion.correction_start().x()), 1e-6 * amplitude);
  EXPECT_FALSE(motion.has_vertical());
}

// A record far longer than the runs is kept only to their end: the kept samples are the
// whole record's (bit for bit, its baseline correction included, which spans the whole
// record), one sample past the end, and the record's end is remembered. A 300 s record
// for a 0.2 s run is 0.2 s of samples, not 300 s.
TEST(GroundMotion, ALongRecordIsKeptOnlyToTheEndOfTheRuns) {
  const double step = 1e-3;
  const AccelerationRecord record = sine_train(1.5, 2.0, 300.0, 1.0, 0.01);
  const GroundMotion whole(record, {}, 0.5, step, true);
  const GroundMotion kept(record, {}, 0.5, step, true, 0.7);
  EXPECT_FALSE(whole.cut());
  ASSERT_TRUE(kept.cut());
  EXPECT_EQ(kept.acceleration_samples().size(), 202u);  // τ = 0 … 0.201 s
  EXPECT_GE(kept.end_time(), 0.7);
  EXPECT_DOUBLE_EQ(kept.record_end_time(), whole.end_time());
  EXPECT_EQ(kept.correction_start().x(), whole.correction_start().x());
  EXPECT_EQ(kept.correction_end().x(), whole.correction_end().x());
  for (std::size_t k = 0; k < kept.acceleration_samples().size(); ++k) {
    ASSERT_EQ(kept.acceleration_samples()[k], whole.acceleration_samples()[k]) << k;
    ASSERT_EQ(kept.velocity_samples()[k], whole.velocity_samples()[k]) << k;
    ASSERT_EQ(kept.displacement_samples()[k], whole.displacement_samples()[k]) << k;
  }
  // what a checkpoint holds of it comes back cut, with the record's end
  const GroundMotion read(kept.start_time(), kept.step(), kept.acceleration_samples(),
                          kept.velocity_samples(), kept.displacement_samples(),
                          kept.record_end_time());
  EXPECT_TRUE(read.cut());
  EXPECT_DOUBLE_EQ(read.record_end_time(), whole.end_time());
  // a run that ends before the motion starts keeps two samples
  EXPECT_EQ(GroundMotion(record, {}, 0.5, step, true, 0.1).acceleration_samples().size(), 2u);
}

// A record too long for the solver's step is refused, naming its samples.
TEST(GroundMotion, ARecordOfTooManyStepsIsRefused) {
  const AccelerationRecord two_lines{{0.0, 3400.0}, {0.0, 1.0}};
  EXPECT_NE(message_of([&] {
              GroundMotion(two_lines, {}, 0.0, 1e-6, true, 1.0);
            }).find("motion: 3400 s sampled every 1e-06 s is 3.4e+09 samples (at most 5e+08)"),
            std::string::npos);
}

// A record whose velocity drifts (a constant acceleration) is corrected so that its
// discrete velocity and displacement end at exactly zero, and the base is at rest
// before the start and after the end.
TEST(GroundMotion, BaselineCorrectionEndsVelocityAndDisplacementAtZero) {
  AccelerationRecord record{{0.0, 1.0, 2.0}, {0.5, 0.5, 0.5}};
  const double step = 0.01;
  const GroundMotion corrected(record, record, 2.0, step, true);
  const auto& v = corrected.velocity_samples();
  const auto& u = corrected.displacement_samples();
  EXPECT_EQ(v.size(), 201u);
  EXPECT_LT(v.back().norm(), 1e-13);
  EXPECT_LT(u.back().norm(), 1e-13);
  EXPECT_EQ(corrected.displacement(1.9), Vec2::Zero());  // before the start
  EXPECT_EQ(corrected.velocity(5.0), Vec2::Zero());      // after the end
  EXPECT_TRUE(corrected.has_vertical());
  const GroundMotion raw(record, {}, 2.0, step, false);
  EXPECT_NEAR(raw.velocity_samples().back().x(), 1.0, 1e-12);     // ∫ 0.5 dt over 2 s
  EXPECT_NEAR(raw.displacement_samples().back().x(), 1.0, 1e-9);  // 0.5 · 2²/2
}

// A prescribed base moves by whole displacement increments: over any sequence of steps,
// even steps shorter than the sampling, Σ step_velocity · dt is u_g at the end, and the
// step velocity of each is the exact mean velocity over that step (the Ricker's
// displacement is −A/(2b) exp(−b (τ − τ_p)²)): the Hermite interpolation gives a short
// step the velocity of its own instant, not the mean of the sampling interval.
TEST(GroundMotion, StepVelocitiesAddUpToTheDisplacementAndFollowTheVelocity) {
  const double amplitude = 3.0, f = 4.0, tp = 0.3, step = 1e-3;
  const GroundMotion motion(ricker_wavelet(amplitude, f, tp, step), {}, 0.0, step, true);
  const double b = pi * pi * f * f;
  const auto exact_u = [&](double t) {
    return -amplitude / (2 * b) * (std::exp(-b * (t - tp) * (t - tp)) - std::exp(-b * tp * tp));
  };
  const double peak_velocity = motion.peaks().velocity.x();
  double t = 0.0, u = 0.0, worst = 0.0;
  const double steps[] = {7e-4, 1e-5, 1.3e-3, 3e-6, 9e-4};
  for (int k = 0; t < 2 * tp; ++k) {
    const double dt = steps[k % 5];
    const double v = motion.step_velocity(t, dt).x();
    worst = std::max(worst, std::abs(v - (exact_u(t + dt) - exact_u(t)) / dt));
    u += v * dt;
    t += dt;
  }
  // The sampled velocity is the trapezoidal integral of a: its error is at most
  // (T/12) Δτ² max|a''|, and max|a''| = |a''(τ_p)| = 6 A b for the Ricker.
  EXPECT_LT(worst, 2 * tp / 12 * step * step * 6 * amplitude * b);
  EXPECT_LT(worst, 2e-4 * peak_velocity);
  EXPECT_NEAR(u, motion.displacement(t).x(), 1e-12);
}

TEST(GroundMotion, SineTrainIsTaperedAtBothEnds) {
  const auto record = sine_train(1.0, 1.0, 4.0, 1.0, 0.01);
  EXPECT_DOUBLE_EQ(record.time.back(), 4.0);
  EXPECT_NEAR(record.acceleration.front(), 0.0, 1e-15);
  EXPECT_NEAR(record.acceleration.back(), 0.0, 1e-12);
  // Between the tapers the full amplitude: sin(2π · 1.25) = 1.
  EXPECT_NEAR(record.acceleration[125], 1.0, 1e-12);
  // Inside the taper w = (1 − cos(π τ/T))/2: at τ = 0.5 s, w = 0.5, sin(π) = 0; at
  // τ = 0.25 s, w = (1 − cos(π/4))/2, sin(π/2) = 1.
  EXPECT_NEAR(record.acceleration[25], 0.5 * (1 - std::cos(pi / 4)), 1e-12);
}

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "slide-test-ground-motion";
  std::filesystem::create_directories(dir);
  return dir / name;
}

std::filesystem::path write_file(const std::string& name, const std::string& text) {
  const auto path = scratch(name);
  std::ofstream(path) << text;
  return path;
}

TEST(MotionFile, ReadsColumnsInGAndRejectsBadRecords) {
  const auto good = write_file("good.txt", "# t a\n0 0\n0.01, 0.1\n\n0.02\t-0.2  # peak\n");
  const AccelerationRecord record = read_motion_file(good, gravity_acceleration);
  ASSERT_EQ(record.time.size(), 3u);
  EXPECT_DOUBLE_EQ(record.acceleration[1], 0.1 * gravity_acceleration);
  EXPECT_DOUBLE_EQ(record.time[2], 0.02);
  const auto error = [](const std::string& text) {
    const auto path = write_file("bad.txt", text);
    return message_of([&] { read_motion_file(path, 1.0); });
  };
  EXPECT_NE(error("0 0\n0.01 1 2\n").find("bad.txt:2: 3 numbers, expected 2"), std::string::npos);
  EXPECT_NE(error("0 0\n0.02 1\n0.01 1\n").find("bad.txt:3: time 0.01 s does not follow 0.02 s"),
            std::string::npos);
  EXPECT_NE(error("0 0\n0.01 nan\n").find("bad.txt:2: \"nan\" is not a finite number"),
            std::string::npos);
  EXPECT_NE(error("0 x\n").find("\"x\" is not a finite number"), std::string::npos);
  EXPECT_NE(error("-1 0\n0 0\n").find("the first time is -1 s"), std::string::npos);
  EXPECT_NE(error("0 0\n").find("1 samples, a motion needs at least 2"), std::string::npos);
  EXPECT_NE(message_of([] {
              read_motion_file(scratch("missing.txt"), 1.0);
            }).find("cannot read the motion file"),
            std::string::npos);
}

// ----------------------------------------------------------------------------- case file

std::string column_case(const std::string& motion, const std::string& failure_sides = "roller") {
  return R"([case]
name = "unit-test"

[[materials]]
name = "soil"
model = "linear-elastic"
density = 2000.0
youngs_modulus = 208.0e6
poisson_ratio = 0.3

[mesh]
generator = "profile"
element_size = 0.5
surface = [[0.0, 4.0], [0.5, 4.0]]
material = "soil"

[fem]
end_time = 2.0

[fem.geostatic.boundaries]
left = "roller"
right = "roller"
base = "roller"

[fem.failure.boundaries]
left = ")" +
         failure_sides +
         R"("
right = "roller"
base = "roller"

)" + motion +
         R"(
[transfer]
sweep_times = [0.0]

[mpm]
domain = [[0.0, 0.0], [1.0, 5.0]]
cell_size = 0.5
end_time = 3.0

[mpm.boundaries]
base = "fixed"

[metrics]
initial_length = 0.5
initial_height = 4.0
)";
}

const std::string compliant_ricker = R"([fem.motion]
start_time = 0.5
base = "compliant"
rock_density = 2200.0
rock_shear_wave_speed = 400.0
lateral = "tied"

[fem.motion.horizontal]
source = "ricker"
units = "g"
amplitude = 0.1
peak_frequency = 5.0
peak_time = 0.3

[[fem.recorders]]
name = "surface"
points = [[0.0, 4.0]]
every = 0.01
)";

TEST(CaseFile, MotionAndRecordersLoad) {
  const Case c = parse_case(column_case(compliant_ricker), "case.toml");
  ASSERT_TRUE(c.fem.motion);
  const MotionSpec& m = *c.fem.motion;
  EXPECT_EQ(m.base, SeismicBase::compliant);
  EXPECT_EQ(m.lateral, LateralBoundary::tied);
  EXPECT_EQ(m.input, MotionInput::incident);
  EXPECT_DOUBLE_EQ(m.start_time, 0.5);
  ASSERT_TRUE(m.horizontal);
  EXPECT_FALSE(m.vertical);
  EXPECT_DOUBLE_EQ(m.horizontal->amplitude, 0.1 * gravity_acceleration);
  ASSERT_EQ(c.fem.recorders.size(), 1u);
  EXPECT_EQ(c.fem.recorders[0].name, "surface");
  EXPECT_DOUBLE_EQ(c.fem.recorders[0].every, 0.01);
  const GroundMotion motion = make_ground_motion(m, 1e-3, c.fem.end_time);
  EXPECT_NEAR(motion.end_time(), 0.5 + 0.6, 1e-12);
  EXPECT_FALSE(motion.cut());
}

TEST(CaseFile, MotionMistakesAreOneLineErrors) {
  const auto error = [](const std::string& motion, const std::string& sides = "roller") {
    return message_of([&] { parse_case(column_case(motion, sides), "case.toml"); });
  };
  const auto replaced = [](std::string text, const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  EXPECT_NE(error(replaced(compliant_ricker, "peak_time = 0.3", "peak_time = 0.1"))
                .find("fem.motion.horizontal.peak_time = 0.1 is not admissible (expected ≥ 0.2 s"),
            std::string::npos);
  EXPECT_NE(error(replaced(compliant_ricker, "rock_shear_wave_speed = 400.0\n", ""))
                .find("fem.motion.rock_shear_wave_speed: missing required key"),
            std::string::npos);
  EXPECT_NE(error(replaced(compliant_ricker, "units = \"g\"", "units = \"gal\""))
                .find("fem.motion.horizontal.units = \"gal\" is not admissible (expected one of: "
                      "m/s2, g)"),
            std::string::npos);
  EXPECT_NE(error(replaced(compliant_ricker, "peak_time = 0.3", "peak_time = 0.3\nduration = 1"))
                .find("fem.motion.horizontal.duration: not used by source = \"ricker\""),
            std::string::npos);
  EXPECT_NE(error(replaced(compliant_ricker, "start_time = 0.5", "start_time = 2.5"))
                .find("fem.motion.start_time: 2.5 s is not before fem.end_time = 2 s"),
            std::string::npos);
  EXPECT_NE(error(compliant_ricker, "free").find("needs fem.failure.boundaries.left = \"roller\""),
            std::string::npos);
  EXPECT_NE(error(replaced(compliant_ricker, "every = 0.01", "every = 0.01\nnode_set = \"base\""))
                .find("give exactly one of points, node_set, elements (found 2)"),
            std::string::npos);
  EXPECT_NE(error(replaced(compliant_ricker, "name = \"surface\"", "name = \"a/b\""))
                .find("\"a/b\" is not a file name"),
            std::string::npos);
  EXPECT_NE(error("[fem.motion]\nbase = \"rigid\"\n").find("no motion"), std::string::npos);
}

TEST(CaseFile, MpmRecordersLoadAndTheirMistakesAreOneLineErrors) {
  const std::string recorder = "\n[[mpm.recorders]]\nname = \"crest\"\npoints = [[0.0, 4.0]]\n";
  const Case c = parse_case(column_case("") + recorder + "every = 0.5\n", "case.toml");
  ASSERT_EQ(c.mpm.recorders.size(), 1u);
  EXPECT_EQ(c.mpm.recorders[0].name, "crest");
  ASSERT_EQ(c.mpm.recorders[0].points.size(), 1u);
  EXPECT_EQ(c.mpm.recorders[0].points[0], Vec2(0.0, 4.0));
  EXPECT_DOUBLE_EQ(c.mpm.recorders[0].every, 0.5);
  const auto error = [](const std::string& text) {
    return message_of([&] { parse_case(column_case("") + text, "case.toml"); });
  };
  EXPECT_NE(error(recorder + recorder).find("mpm.recorders[1].name: \"crest\" twice"),
            std::string::npos)
      << error(recorder + recorder);
  EXPECT_NE(error("\n[[mpm.recorders]]\nname = \"a b\"\npoints = [[0.0, 4.0]]\n")
                .find("\"a b\" is not a file name"),
            std::string::npos);
  EXPECT_NE(error("\n[[mpm.recorders]]\nname = \"x\"\npoints = []\n").find("an empty list"),
            std::string::npos);
  EXPECT_NE(error("\n[[mpm.recorders]]\nname = \"x\"\n").find("points: missing required key"),
            std::string::npos)
      << error("\n[[mpm.recorders]]\nname = \"x\"\n");
  EXPECT_NE(error(recorder + "every = -1\n").find("every = -1 is not admissible"),
            std::string::npos);
  EXPECT_NE(error(recorder + "node_set = \"base\"\n").find("node_set"), std::string::npos);
}

}  // namespace
}  // namespace slide
