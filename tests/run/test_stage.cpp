// The shared run loop: where it stops, what it asks the stage to write, an early end;
// the guard's energy check at its tolerance.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "common/base/error.hpp"
#include "common/run/stability_guard.hpp"
#include "common/run/stage.hpp"

namespace slide::run {
namespace {

/// A stage that records the loop's requests; it comes to rest at `rest_time`.
class RecordingStage final : public Stage {
 public:
  explicit RecordingStage(double rest_time = std::numeric_limits<double>::infinity())
      : rest_time_(rest_time) {}
  double time() const override { return time_; }
  bool advance_to(double stop) override {
    if (stop > rest_time_) {
      time_ = rest_time_;
      return false;
    }
    time_ = stop;
    return true;
  }
  void write_output(bool checkpoint) override { outputs.push_back({time_, checkpoint}); }

  struct Output {
    double time;
    bool checkpoint;
  };
  std::vector<Output> outputs;

 private:
  double time_ = 0.0;
  double rest_time_;
};

TEST(Drive, WritesAtEveryStopWithTheCheckpointsTheScheduleHas) {
  const OutputSchedule schedule(1.0, 0.25, {0.5}, {});
  RecordingStage stage;
  EXPECT_TRUE(drive(stage, schedule, true));
  ASSERT_EQ(stage.outputs.size(), 4U);
  const double times[] = {0.25, 0.5, 0.75, 1.0};
  const bool checkpoints[] = {false, true, false, true};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(stage.outputs[i].time, times[i]);
    EXPECT_EQ(stage.outputs[i].checkpoint, checkpoints[i]) << "at " << times[i];
  }
  RecordingStage no_end_checkpoint;
  const OutputSchedule odd_end(0.9, 0.25, {0.5}, {});
  EXPECT_TRUE(drive(no_end_checkpoint, odd_end, false));
  EXPECT_EQ(no_end_checkpoint.outputs.back().time, 0.9);
  EXPECT_FALSE(no_end_checkpoint.outputs.back().checkpoint);
}

TEST(Drive, AStageAtRestEndsTheLoopAfterWritingItsState) {
  const OutputSchedule schedule(1.0, 0.25, {}, {});
  RecordingStage stage(0.6);
  EXPECT_FALSE(drive(stage, schedule, true));
  ASSERT_EQ(stage.outputs.size(), 3U);
  EXPECT_EQ(stage.outputs.back().time, 0.6);
  EXPECT_FALSE(stage.outputs.back().checkpoint);
}

TEST(Drive, AStageAtItsEndTimeWritesNothing) {
  const OutputSchedule schedule(1.0, 0.25, {}, {});
  RecordingStage done;
  for (double t : {0.25, 0.5, 0.75, 1.0}) done.advance_to(t);
  EXPECT_TRUE(drive(done, schedule, true));
  EXPECT_TRUE(done.outputs.empty());
}

TEST(EnergyGrowth, TheToleranceIsFivePerCentOfTheScale) {
  const EnergyReference reference{100.0, 1000.0};
  EXPECT_FALSE(energy_growth(100.0 + 49.9, reference));
  EXPECT_FALSE(energy_growth(-5000.0, reference));  // dissipation is never a problem
  const auto grown = energy_growth(100.0 + 50.1, reference, "kinetic 1 J/m");
  ASSERT_TRUE(grown);
  EXPECT_NE(grown->find("grew by 50.1 J/m (5.01 % of the releasable energy 1000 J/m"),
            std::string::npos)
      << *grown;
  EXPECT_NE(grown->find("(kinetic 1 J/m)"), std::string::npos) << *grown;
  EXPECT_TRUE(energy_growth(std::numeric_limits<double>::quiet_NaN(), reference));
  EXPECT_TRUE(energy_growth(std::numeric_limits<double>::infinity(), reference));
}

TEST(SpeedLimit, IsTheFactorTimesTheFreeFallSpeedOverTheHeight) {
  EXPECT_DOUBLE_EQ(speed_limit(3.0, 9.81, 40.0), 3.0 * std::sqrt(2.0 * 9.81 * 40.0));
}

TEST(CheckRestartMaterials, NamesTheFirstDifference) {
  Material soil;
  soil.name = "soil";
  soil.density = 2000.0;
  Material denser = soil;
  denser.density = 2100.0;
  EXPECT_NO_THROW(check_restart_materials({soil}, {soil}, "x.h5"));
  EXPECT_THROW(check_restart_materials({soil}, {soil, soil}, "x.h5"), Error);
  try {
    check_restart_materials({soil}, {denser}, "x.h5");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.h5: material \"soil\" has density 2000"),
              std::string::npos)
        << e.what();
  }
}

TEST(CheckpointNames, ACadenceOrListTheNamesCannotTellApartIsRefused) {
  EXPECT_NO_THROW(check_checkpoint_cadence(0.0, "x"));  // no cadence
  EXPECT_NO_THROW(check_checkpoint_cadence(0.001, "x"));
  EXPECT_THROW(check_checkpoint_cadence(0.0004, "x"), Error);
  EXPECT_THROW(check_checkpoint_cadence(1e-12, "x"), Error);
  EXPECT_NO_THROW(check_checkpoint_times({0.5, 1.0, 1.001}, "fem", "x", {0.0}));
  EXPECT_NO_THROW(check_checkpoint_times({0.3, 0.1 * 3}, "fem", "x"));  // one time
  try {
    check_checkpoint_times({0.0004, 1.0}, "fem", "fem.checkpoint_times", {0.0});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("0 s and 0.0004 s would both be fem_t0.000.h5"),
              std::string::npos)
        << e.what();
  }
}

// fem-solve and mpm-solve call this at the start of a run: a killed run's temporaries in
// OUT and OUT/vtk go, those of a live process and every other file stay.
TEST(RemoveTemporariesOfKilledRuns, OnlyThoseOfGoneProcesses) {
  namespace fs = std::filesystem;
  const fs::path out = fs::path(SLIDE_BINARY_DIR) / "test-scratch" / "stage" / "temporaries";
  fs::remove_all(out);
  fs::create_directories(out / "vtk");
  const std::string gone = ".tmp-999999999";  // above any pid the kernel hands out
  const std::string live = ".tmp-" + std::to_string(::getpid());
  for (const fs::path& f :
       {out / (".fem_t0.890.h5" + gone), out / "vtk" / (".fem_000018.vtu" + gone),
        out / (".fem_history.csv" + live), out / "fem_t1.000.h5", out / "notes.tmp-999999999"}) {
    std::ofstream(f) << "x";
  }
  remove_temporaries_of_killed_runs(out, Logger("test", true));
  EXPECT_FALSE(fs::exists(out / (".fem_t0.890.h5" + gone)));
  EXPECT_FALSE(fs::exists(out / "vtk" / (".fem_000018.vtu" + gone)));
  EXPECT_TRUE(fs::exists(out / (".fem_history.csv" + live)));
  EXPECT_TRUE(fs::exists(out / "fem_t1.000.h5"));
  EXPECT_TRUE(fs::exists(out / "notes.tmp-999999999"));  // not hidden: not ours
  EXPECT_NO_THROW(remove_temporaries_of_killed_runs(out / "missing", Logger("test", true)));
}

TEST(CheckpointFileName, HasThreeDecimals) {
  EXPECT_EQ(checkpoint_file_name("fem", 2.0), "fem_t2.000.h5");
  EXPECT_EQ(checkpoint_file_name("mpm", 0.1 * 3), "mpm_t0.300.h5");
}

}  // namespace
}  // namespace slide::run
