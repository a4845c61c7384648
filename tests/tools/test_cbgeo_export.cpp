// CB-Geo MPM export (tools/interop/cbgeo_export.hpp) in memory: four particles of a small
// column case. What the export does not carry over is listed, one note per setting, and
// only when the case or the particles have it; cadences that would make a nonsense step or
// output count, and numbers mpm.json cannot hold, are refused before anything is written.
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/input/case_file.hpp"
#include "common/io/checkpoint.hpp"
#include "tests/support/column_case.hpp"
#include "tests/support/errors.hpp"
#include "tools/interop/cbgeo_export.hpp"

namespace slide {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using testing::error_of;
using ::testing::HasSubstr;
using ::testing::Not;

/// The column case (grid [0, 40] × [0, 20] m of 1 m cells, mpm.end_time = 1 s), with
/// `extra_mpm` lines added to its [mpm] table.
Case column_case(const std::string& extra_mpm = "") {
  std::string text = slide::testing::ColumnCase{}.text();
  text.replace(text.find("[mpm]\n"), 6, "[mpm]\n" + extra_mpm);
  return parse_case(text, "case.toml");
}

/// Four particles of the case's soil in the grid's lower-left cell, at rest, at t = 0.
ParticleCheckpoint four_particles(const Case& c) {
  ParticleCheckpoint checkpoint;
  checkpoint.header.kind = CheckpointKind::particles;
  checkpoint.header.case_name = c.name;
  checkpoint.materials = c.materials;
  Particles& p = checkpoint.particles;
  p.resize(4);
  for (std::size_t i = 0; i < 4; ++i) {
    p.coordinates[i] = Vec2(0.25 + 0.5 * static_cast<double>(i % 2), 0.25 + 0.5 * (i < 2 ? 0 : 1));
    p.volume[i] = 0.25;
    p.mass[i] = c.materials[0].density * 0.25;
    p.size[i] = Vec2(0.5, 0.5);
    p.id[i] = static_cast<std::int64_t>(i);
    p.stress[i] = Vec4(-1e4, -2e4, -0.7e4, 0.0);
  }
  return checkpoint;
}

std::vector<std::string> notes_of(const Case& c, const ParticleCheckpoint& checkpoint,
                                  const interop::CbGeoExportOptions& options = {}) {
  return interop::export_cbgeo(c, checkpoint, options).notes;
}

/// Whether a note starts with `start`.
auto note_starting(const std::string& start) {
  return Contains(::testing::StartsWith(start));
}

TEST(CbGeoExport, ListsTheDefaultsItDoesNotCarryOver) {
  const Case c = column_case();
  const std::vector<std::string> notes = notes_of(c, four_particles(c));
  EXPECT_THAT(notes, note_starting("time step: mpm-solve's Courant step, renewed as the "
                                   "particles deform, written as CB-Geo's fixed dt = "));
  EXPECT_THAT(notes, note_starting("mpm.particle_exit = \"freeze\": CB-Geo removes the particles "
                                   "that leave the grid"));
  EXPECT_THAT(notes, note_starting("mpm.speed_limit_factor = 5: CB-Geo has no instability guard"));
  // Nothing the case and the particles do not have.
  for (const char* absent : {"gravity_angle", "base motion", "pore pressures", "frozen particles",
                             "rest stop", "mpm.checkpoint_times", "velocity transfer"}) {
    EXPECT_THAT(notes, Not(note_starting(absent))) << absent;
  }
}

TEST(CbGeoExport, ListsTheCaseSettingsItDoesNotCarryOver) {
  Case c = column_case(
      "pic_fraction = 0.3\nrest_threshold = 0.01\nrest_duration = 0.5\ncheckpoint_times = [0.5]\n"
      "particle_exit = \"remove\"\ntime_step = 1e-4\n");
  const double theta = 10.0 * std::numbers::pi / 180.0;
  c.gravity = 9.81 * Vec2(std::sin(theta), -std::cos(theta));  // [case] gravity_angle = 10
  c.fem.motion = MotionSpec{};
  const std::vector<std::string> notes = notes_of(c, four_particles(c));
  EXPECT_THAT(notes, note_starting("gravity_angle: the case turns gravity by 10° to (1.70349, "
                                   "-9.66096) m/s²; mpm.json's gravity is (0, -9.81) m/s²"));
  EXPECT_THAT(notes, note_starting("base motion: the case's [fem.motion] is not written (the "
                                   "particle file has no /motion either)"));
  EXPECT_THAT(notes, note_starting("velocity transfer: the FLIP/PIC blend mpm.pic_fraction = 0.3 "
                                   "written as FLIP"));
  EXPECT_THAT(notes, note_starting("rest stop (mpm.rest_threshold = 0.01 for mpm.rest_duration = "
                                   "0.5 s): CB-Geo has none"));
  EXPECT_THAT(notes, note_starting("mpm.checkpoint_times: CB-Geo writes its state at the regular "
                                   "cadence only, not at the 1 listed time(s)"));
  // Carried: particles removed at the grid's edge, the case's fixed step.
  EXPECT_THAT(notes, Not(note_starting("mpm.particle_exit")));
  EXPECT_THAT(notes, Not(note_starting("time step")));
}

TEST(CbGeoExport, ListsTheStateItDoesNotCarryOver) {
  const Case c = column_case();
  ParticleCheckpoint checkpoint = four_particles(c);
  checkpoint.header.kind = CheckpointKind::mpm;
  checkpoint.header.time = 0.02;
  checkpoint.particles.pore_pressure[2] = -1500.0;
  checkpoint.solver["frozen_particles"] = std::int64_t{1};
  // A rigid base moving at 1 m/s along x since t = 0, its samples every 0.01 s.
  CheckpointMotion motion;
  motion.step = 0.01;
  motion.acceleration.assign(4, Vec2::Zero());
  motion.velocity.assign(4, Vec2(1.0, 0.0));
  motion.displacement = {Vec2(0.0, 0.0), Vec2(0.01, 0.0), Vec2(0.02, 0.0), Vec2(0.03, 0.0)};
  motion.base = "rigid";
  motion.input = "incident";
  checkpoint.motion = motion;
  const std::vector<std::string> notes = notes_of(c, checkpoint);
  EXPECT_THAT(notes, note_starting("base motion: the file's /motion (4 samples every 0.01 s from "
                                   "t = 0 s, rigid base) is not written: CB-Geo's grid stays at "
                                   "rest at mpm.domain, while mpm-solve moves it with the base "
                                   "(by (0.02, 0) m at t = 0.02 s)"));
  EXPECT_THAT(notes, note_starting("pore pressures (up to 1500 Pa): CB-Geo's single-phase"));
  EXPECT_THAT(notes, note_starting("frozen particles: 1 that mpm-solve froze at the grid's edge "
                                   "are written as ordinary particles"));
}

TEST(CbGeoExport, RefusesCadencesThatMakeNoSenseBeforeWriting) {
  const Case c = column_case();
  const ParticleCheckpoint checkpoint = four_particles(c);
  const auto error = [&](interop::CbGeoExportOptions options) {
    return error_of([&] { interop::export_cbgeo(c, checkpoint, options); });
  };
  // The step: C h / c_p = 0.05 × 1 m / 127.4 m/s = 3.92e-4 s.
  EXPECT_THAT(error({.output_every = 1e-300}),
              AllOf(HasSubstr("--output-every = 1e-300 s is shorter than CB-Geo's time step "
                              "0.000392"),
                    HasSubstr("the Courant step C h / max c_p at --courant 0.05: CB-Geo writes "
                              "its state at most once a step (give --output-every 0.000393 or "
                              "more)")));
  EXPECT_THAT(error({.end_time = 100.0, .output_every = 5e-4}),
              HasSubstr("--output-every = 0.0005 s makes 2e+05 outputs over the 100 s from t = 0 "
                        "to 100 s, more than 1e+05"));
  EXPECT_THAT(error({.end_time = 1e300}),
              AllOf(HasSubstr("the run would take 2.55e+303 steps of 0.000392 s (at most 1e+09)"),
                    HasSubstr("the run 1e+300 s long (t = 0 to 1e+300 s, --end-time)")));
  EXPECT_THAT(error({.courant = 0.0}),
              HasSubstr("--courant 0: expected a Courant number in (0, 1]"));
  // A cadence of one step is the least there is: one output a step.
  const interop::CbGeoInput input =
      interop::export_cbgeo(c, checkpoint, {.end_time = 0.01, .output_every = 3.93e-4});
  EXPECT_TRUE(std::isfinite(input.time_step));
  EXPECT_LE(input.time_step, 3.93e-4);
  EXPECT_EQ(input.steps, std::lround(0.01 / input.time_step) + 1);
}

TEST(CbGeoExport, NeverWritesANumberThatIsNotFinite) {
  Case c = column_case();
  c.mpm.local_damping = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_of([&] { interop::export_cbgeo(c, four_particles(c), {}); }),
            "mpm.json: analysis.damping.damping_factor = nan, expected a finite number (nothing "
            "written)");
}

}  // namespace
}  // namespace slide
