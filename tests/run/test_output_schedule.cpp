// Where fem-solve and mpm-solve stop: output grid, checkpoint cadences and lists, the
// end time; and which of those stops write a VTK frame.
#include <string>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/run/output_schedule.hpp"

namespace slide::run {
namespace {

TEST(OutputSchedule, StopsOnTheOutputGridAndTheCheckpointTimes) {
  const OutputSchedule schedule(1.0, 0.1, {0.5}, {0.25});
  std::vector<double> stops;
  for (double t = 0.0; t < 1.0;) {
    t = schedule.next_stop(t);
    stops.push_back(t);
  }
  ASSERT_EQ(stops.size(), 11U);
  EXPECT_DOUBLE_EQ(stops[0], 0.1);
  EXPECT_DOUBLE_EQ(stops[2], 0.25);
  EXPECT_DOUBLE_EQ(stops[3], 0.3);
  EXPECT_EQ(stops.back(), 1.0);
  EXPECT_TRUE(schedule.is_checkpoint(0.25));
  EXPECT_TRUE(schedule.is_checkpoint(5 * 0.1));
  EXPECT_TRUE(schedule.is_checkpoint(1.0));
  EXPECT_FALSE(schedule.is_checkpoint(0.3));
}

TEST(OutputSchedule, GridTimesAreMultiplesNotSums) {
  // 0.1·3 = 0.30000000000000004 in binary; a restart at that time continues with 0.4.
  const OutputSchedule schedule(1.0, 0.1, {}, {});
  EXPECT_EQ(schedule.next_stop(0.1 * 3), 0.1 * 4);
  EXPECT_EQ(schedule.next_stop(0.0), 0.1);
}

TEST(OutputSchedule, TimesWithinTheToleranceAreOneStop) {
  // A listed 0.3 and the grid's 0.30000000000000004 must not make a 5e-17 s step.
  const OutputSchedule schedule(1.0, 0.1, {}, {0.3});
  const double stop = schedule.next_stop(0.2);
  EXPECT_NEAR(stop, 0.3, 1e-15);
  EXPECT_NEAR(schedule.next_stop(stop), 0.4, 1e-15);
  EXPECT_TRUE(schedule.is_checkpoint(0.1 * 3));
}

TEST(OutputSchedule, WithoutOutputCadenceStopsAtCheckpointsOnly) {
  const OutputSchedule schedule(2.0, 0.0, {1.0, 0.0}, {});
  EXPECT_EQ(schedule.next_stop(0.0), 1.0);
  EXPECT_EQ(schedule.next_stop(1.0), 2.0);
  EXPECT_EQ(schedule.next_stop(1.9999999999), 2.0);
}

}  // namespace
}  // namespace slide::run

namespace slide::run {
namespace {

// About automatic_vtk_frames frames a stage, on output steps: the smallest whole multiple
// of the output step that keeps the count at or below 100.
TEST(VtkCadence, AutomaticIsTheSmallestMultipleOfTheOutputStepForAHundredFrames) {
  EXPECT_DOUBLE_EQ(automatic_vtk_every(0.0, 1.0, 0.01), 0.01);   // 100 outputs: every one
  EXPECT_DOUBLE_EQ(automatic_vtk_every(0.0, 1.01, 0.01), 0.02);  // 101: every second one
  EXPECT_DOUBLE_EQ(automatic_vtk_every(2.0, 20.0, 0.1), 0.2);    // column-short's MPM: 90
  EXPECT_DOUBLE_EQ(automatic_vtk_every(0.0, 8.0, 0.1), 0.1);     // its FE phase: 80
  EXPECT_DOUBLE_EQ(automatic_vtk_every(0.0, 1000.0, 0.5), 10.0);
  EXPECT_EQ(automatic_vtk_every(0.0, 10.0, 0.0), 0.0) << "outputs only at checkpoints: each";
  EXPECT_EQ(automatic_vtk_every(5.0, 5.0, 0.1), 0.1) << "a stage of no length";
}

TEST(VtkCadence, FramesAtTheCadenceAndAlwaysAtStartCheckpointsAndEnd) {
  EXPECT_TRUE(is_vtk_frame(0.4, 0.2, false));
  EXPECT_FALSE(is_vtk_frame(0.5, 0.2, false));
  EXPECT_TRUE(is_vtk_frame(0.5, 0.2, true));
  EXPECT_TRUE(is_vtk_frame(0.5, 0.0, false)) << "0: every output step";
  EXPECT_TRUE(is_vtk_frame(0.6000000000000001, 0.2, false)) << "within the grid's tolerance";
}

TEST(VtkCadence, ACadenceOffTheOutputStepsIsRefusedNamingIt) {
  EXPECT_NO_THROW(check_vtk_every(0.3, 0.1, "--vtk-every"));
  EXPECT_NO_THROW(check_vtk_every(0.0, 0.1, "--vtk-every"));
  EXPECT_NO_THROW(check_vtk_every(0.07, 0.0, "--vtk-every")) << "no output grid to land on";
  try {
    check_vtk_every(0.07, 0.05, "--vtk-every");
    FAIL() << "0.07 s accepted on an output step of 0.05 s";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--vtk-every = 0.07 s is not a whole multiple"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace slide::run
