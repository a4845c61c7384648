// The shared run lifecycle: where it stops, what it asks the stage to write (rows,
// frames, checkpoints), the guard before every output, an early end; the guard's energy
// check at its tolerance; the restart record's writer and validator.
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "common/base/error.hpp"
#include "common/run/output_lock.hpp"
#include "common/run/restart_record.hpp"
#include "common/run/stability_guard.hpp"
#include "common/run/stage.hpp"

namespace slide::run {
namespace {

/// A stage that records what the lifecycle asks of it; it comes to rest at `rest_time`,
/// and its guard fails from `unstable_time` on.
class RecordingStage final : public Stage {
 public:
  explicit RecordingStage(double rest_time = std::numeric_limits<double>::infinity(),
                          StartOutput first = StartOutput::first)
      : rest_time_(rest_time), first_(first) {}
  double time() const override { return time_; }
  std::int64_t step() const override { return steps_; }
  void open_outputs(bool resume) override { opened_resumed = resume; }
  StartOutput start() override {
    started = true;
    return first_;
  }
  bool advance_to(double stop) override {
    ++steps_;
    if (stop > rest_time_) {
      time_ = rest_time_;
      return false;
    }
    time_ = stop;
    return true;
  }
  std::optional<std::string> check_stability() override {
    ++checks;
    if (time_ >= unstable_time) return std::string("planted");
    return std::nullopt;
  }
  void write_output(const OutputStep& step) override {
    outputs.push_back({time_, !step.checkpoint.empty(), step.frame, step.checkpoint});
  }
  void finish() override { finished = true; }
  Work work() const override { return {steps_, "point", 3, 3.0 * static_cast<double>(steps_)}; }
  OutputSizes output_sizes() const override { return sizes; }

  struct Output {
    double time;
    bool checkpoint;
    bool frame;
    std::filesystem::path file;
  };
  std::vector<Output> outputs;
  bool started = false, finished = false;
  std::optional<bool> opened_resumed;
  int checks = 0;
  OutputSizes sizes{1000.0, 1000.0};
  double unstable_time = std::numeric_limits<double>::infinity();
  double time_ = 0.0;

 private:
  std::int64_t steps_ = 0;
  double rest_time_;
  StartOutput first_;
};

std::filesystem::path scratch(const std::string& name) {
  const auto folder = std::filesystem::path(SLIDE_BINARY_DIR) / "test-scratch" / "stage" / name;
  std::filesystem::remove_all(folder);
  return folder;
}

Plan plan_of(const OutputSchedule& schedule, const std::string& name, bool checkpoint_at_end,
             bool checkpoint_at_start = false) {
  Plan plan;
  plan.schedule = schedule;
  plan.output = {scratch(name), "fem", true, 0.5, checkpoint_at_end, checkpoint_at_start};
  return plan;
}

const Logger quiet("test", true);

TEST(Execute, WritesAtEveryStopWithTheCheckpointsTheScheduleHas) {
  const Plan plan = plan_of(OutputSchedule(1.0, 0.25, {0.5}, {}), "stops", true);
  RecordingStage stage(std::numeric_limits<double>::infinity(), StartOutput::none);
  const RunResult result = execute(stage, plan, quiet);
  EXPECT_TRUE(result.reached_end);
  EXPECT_TRUE(stage.started && stage.finished);
  EXPECT_EQ(stage.opened_resumed, false);
  EXPECT_TRUE(std::filesystem::is_directory(plan.output.folder));
  ASSERT_EQ(stage.outputs.size(), 4U);
  const double times[] = {0.25, 0.5, 0.75, 1.0};
  const bool checkpoints[] = {false, true, false, true};  // 1.0: checkpoint_at_end
  const bool frames[] = {false, true, false, true};       // every 0.5 s and at checkpoints
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(stage.outputs[i].time, times[i]);
    EXPECT_EQ(stage.outputs[i].checkpoint, checkpoints[i]) << "at " << times[i];
    EXPECT_EQ(stage.outputs[i].frame, frames[i]) << "at " << times[i];
  }
  EXPECT_EQ(stage.outputs[1].file, plan.output.folder / "fem_t0.500.h5");
  EXPECT_EQ(stage.checks, 4);  // the guard before every output
  EXPECT_EQ(result.work.steps, 4);

  RecordingStage no_end_checkpoint(std::numeric_limits<double>::infinity(), StartOutput::none);
  execute(no_end_checkpoint, plan_of(OutputSchedule(0.9, 0.25, {0.5}, {}), "odd", false), quiet);
  EXPECT_EQ(no_end_checkpoint.outputs.back().time, 0.9);
  EXPECT_FALSE(no_end_checkpoint.outputs.back().checkpoint);
}

TEST(Execute, TheFirstOutputHasAFrameAndACheckpointOnlyWhereThePlanSaysSo) {
  const OutputSchedule schedule(1.0, 0.25, {0.5}, {});
  RecordingStage fem_like;  // fem-solve: the start is fem_t0.000.h5 already
  execute(fem_like, plan_of(schedule, "first-fem", true, false), quiet);
  ASSERT_EQ(fem_like.outputs.size(), 5U);
  EXPECT_EQ(fem_like.outputs[0].time, 0.0);
  EXPECT_TRUE(fem_like.outputs[0].frame);
  EXPECT_FALSE(fem_like.outputs[0].checkpoint);
  RecordingStage mpm_like;  // mpm-solve: mpm_t<start>.h5
  execute(mpm_like, plan_of(schedule, "first-mpm", false, true), quiet);
  EXPECT_TRUE(mpm_like.outputs[0].frame);
  EXPECT_TRUE(mpm_like.outputs[0].checkpoint);
  // A restart whose history lacks its time (0.3 s, off the frame cadence and the schedule):
  // a row like any other, no frame, no checkpoint.
  RecordingStage row(std::numeric_limits<double>::infinity(), StartOutput::row);
  row.time_ = 0.3;
  execute(row, plan_of(schedule, "first-row", false, true), quiet);
  EXPECT_EQ(row.outputs[0].time, 0.3);
  EXPECT_FALSE(row.outputs[0].frame);
  EXPECT_FALSE(row.outputs[0].checkpoint);
}

TEST(Execute, AStageAtRestEndsTheLoopAfterWritingItsState) {
  RecordingStage stage(0.6, StartOutput::none);
  const RunResult result =
      execute(stage, plan_of(OutputSchedule(1.0, 0.25, {}, {}), "rest", true), quiet);
  EXPECT_FALSE(result.reached_end);
  EXPECT_TRUE(stage.finished);
  ASSERT_EQ(stage.outputs.size(), 3U);
  EXPECT_EQ(stage.outputs.back().time, 0.6);
  EXPECT_FALSE(stage.outputs.back().checkpoint);
}

TEST(Execute, AStageAtItsEndTimeWritesNothing) {
  RecordingStage done(std::numeric_limits<double>::infinity(), StartOutput::none);
  done.time_ = 1.0;
  execute(done, plan_of(OutputSchedule(1.0, 0.25, {}, {}), "done", true), quiet);
  EXPECT_TRUE(done.outputs.empty());
}

TEST(Execute, AFailedGuardStopsBeforeTheOutputNamingTheLastCheckpoint) {
  Plan plan = plan_of(OutputSchedule(1.0, 0.25, {0.5}, {}), "guard", true);
  RecordingStage stage(std::numeric_limits<double>::infinity(), StartOutput::none);
  stage.unstable_time = 0.75;
  try {
    execute(stage, plan, quiet);
    FAIL() << "no error";
  } catch (const InstabilityError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("instability at t = 0.75 s (step 3): planted"), std::string::npos)
        << message;
    EXPECT_NE(message.find("the last good checkpoint is " +
                           (plan.output.folder / "fem_t0.500.h5").string()),
              std::string::npos)
        << message;
  }
  EXPECT_EQ(stage.outputs.size(), 2U);  // nothing of the failed step
  EXPECT_FALSE(stage.finished);

  plan.start = Start::restart;  // a restart's last good checkpoint is its own file
  plan.start_file = "from.h5";
  plan.resume_outputs = true;
  RecordingStage restarted(std::numeric_limits<double>::infinity(), StartOutput::none);
  restarted.unstable_time = 0.0;
  try {
    execute(restarted, plan, quiet);
    FAIL() << "no error";
  } catch (const InstabilityError& e) {
    EXPECT_NE(std::string(e.what()).find("the last good checkpoint is from.h5"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(restarted.opened_resumed, true);
}

TEST(Execute, CountsNoMoreOutputsThanTheVolumeCheckAllowedFor) {
  // The closed-form counts bound what the loop writes, for cadences on and off each other.
  for (const auto& [end, output_every, every, vtk_every] :
       std::vector<std::array<double, 4>>{{1.0, 0.25, 0.5, 0.5},
                                          {0.9, 0.1, 0.3, 0.2},
                                          {2.0, 0.0, 0.7, 0.0},
                                          {1.3, 0.05, 0.0, 0.0}}) {
    Plan plan = plan_of(OutputSchedule(end, output_every, {every}, {0.33}), "count", true);
    plan.output.vtk_every = vtk_every;
    RecordingStage stage(std::numeric_limits<double>::infinity(), StartOutput::first);
    execute(stage, plan, quiet);
    double checkpoints = 0.0, frames = 0.0;
    for (const auto& o : stage.outputs) {
      checkpoints += o.checkpoint ? 1.0 : 0.0;
      frames += o.frame ? 1.0 : 0.0;
    }
    EXPECT_LE(checkpoints, plan.schedule.checkpoints_after(0.0)) << "end " << end;
    EXPECT_LE(static_cast<double>(stage.outputs.size()), plan.schedule.outputs_after(0.0));
    EXPECT_LE(frames, plan.schedule.outputs_after(0.0));
  }
}

TEST(Execute, ARunThatWouldFillTheDiskOrTheFolderIsRefusedBeforeItWrites) {
  RecordingStage huge;
  huge.sizes = {1e18, 1e18};  // an exabyte a checkpoint: more than any disk here has free
  const Plan plan = plan_of(OutputSchedule(1.0, 0.25, {0.5}, {}), "volume", true);
  try {
    execute(huge, plan, quiet);
    FAIL() << "an exabyte run was accepted";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("GB free"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("checkpoints of 1e+12 MB"));
  }
  EXPECT_FALSE(huge.started);
  EXPECT_FALSE(std::filesystem::exists(plan.output.folder));  // not even the folder

  RecordingStage many;
  const Plan fine = plan_of(OutputSchedule(1e4, 1e-3, {1e-3}, {}), "files", true);
  try {
    execute(many, fine, quiet);
    FAIL() << "ten million checkpoints were accepted";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("1e+07 checkpoints"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("at most 1e+06 files"));
  }
  EXPECT_FALSE(many.started);
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
// OUT, OUT/vtk and OUT/inputs go (a restart killed while it copied the case into inputs/
// left one there: the kill-restart fault test, seed 309328515), those of a live process
// and every other file stay.
TEST(RemoveTemporariesOfKilledRuns, OnlyThoseOfGoneProcesses) {
  namespace fs = std::filesystem;
  const fs::path out = fs::path(SLIDE_BINARY_DIR) / "test-scratch" / "stage" / "temporaries";
  fs::remove_all(out);
  fs::create_directories(out / "vtk");
  fs::create_directories(out / "inputs");
  const std::string gone = ".tmp-999999999";  // above any pid the kernel hands out
  const std::string live = ".tmp-" + std::to_string(::getpid());
  for (const fs::path& f :
       {out / (".fem_t0.890.h5" + gone), out / "vtk" / (".fem_000018.vtu" + gone),
        out / "inputs" / (".case.toml" + gone), out / (".fem_history.csv" + live),
        out / "fem_t1.000.h5", out / "notes.tmp-999999999"}) {
    std::ofstream(f) << "x";
  }
  remove_temporaries_of_killed_runs(out, Logger("test", true));
  EXPECT_FALSE(fs::exists(out / (".fem_t0.890.h5" + gone)));
  EXPECT_FALSE(fs::exists(out / "vtk" / (".fem_000018.vtu" + gone)));
  EXPECT_FALSE(fs::exists(out / "inputs" / (".case.toml" + gone)));
  EXPECT_TRUE(fs::exists(out / (".fem_history.csv" + live)));
  EXPECT_TRUE(fs::exists(out / "fem_t1.000.h5"));
  EXPECT_TRUE(fs::exists(out / "notes.tmp-999999999"));  // not hidden: not ours
  EXPECT_NO_THROW(remove_temporaries_of_killed_runs(out / "missing", Logger("test", true)));
}

struct TestRecord : RunRecord {
  double step = 0.0;
  std::int64_t count = 0;
  bool flag = false;
};
constexpr std::array<RecordEntry<TestRecord>, 7> test_table{{
    {"stage", &TestRecord::stage},
    {"step", &TestRecord::step, 0.0},
    {"count", &TestRecord::count, 0.0, 10.0},
    {"flag", &TestRecord::flag, 0.0, 1.0, Need::optional},
    {"initial_energy", &TestRecord::initial_energy, -unbounded, unbounded, Need::optional,
     "old_initial_energy"},
    {"energy_scale", &TestRecord::energy_scale, 0.0, unbounded, Need::optional},
    {"boundary_work", &TestRecord::boundary_work, -unbounded, unbounded, Need::optional},
}};

TEST(RestartRecord, ReadsBackWhatItWrites) {
  TestRecord r;
  r.stage = "failure";
  r.step = 1e-3;
  r.count = 7;
  r.flag = true;
  r.set_energy({-5.0, 12.0});
  const SolverSettings written = write_record(r, test_table);
  EXPECT_EQ(written.count("boundary_work"), 0U);  // unset: not written
  EXPECT_EQ(std::get<std::int64_t>(written.at("flag")), 1);
  const TestRecord back = read_record(written, test_table, "x.h5", TestRecord{});
  EXPECT_EQ(back.stage, "failure");
  EXPECT_EQ(back.step, 1e-3);
  EXPECT_EQ(back.count, 7);
  EXPECT_TRUE(back.flag);
  ASSERT_TRUE(back.energy());
  EXPECT_EQ(back.energy()->initial_energy, -5.0);
  EXPECT_FALSE(back.boundary_work);
  SolverSettings old = written;  // an earlier version's key
  old.erase("initial_energy");
  old["old_initial_energy"] = 3.0;
  EXPECT_EQ(read_record(old, test_table, "x.h5", TestRecord{}).initial_energy, 3.0);
}

TEST(RestartRecord, NamesAMissingWrongOrOutOfRangeEntry) {
  TestRecord r;
  r.stage = "s";
  const SolverSettings good = write_record(r, test_table);
  const auto message = [&](const SolverSettings& settings) {
    try {
      read_record(settings, test_table, "x.h5", TestRecord{});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SolverSettings missing = good;
  missing.erase("count");
  EXPECT_EQ(message(missing).find("x.h5: /solver attribute count missing"), 0U) << message(missing);
  SolverSettings wrong = good;
  wrong["step"] = std::string("fast");
  EXPECT_EQ(message(wrong), "x.h5: /solver attribute step has the wrong type");
  for (const auto& [key, value] : std::vector<std::pair<std::string, SettingValue>>{
           {"step", -1.0},
           {"step", std::numeric_limits<double>::quiet_NaN()},
           {"count", std::int64_t{11}},
           {"flag", std::int64_t{2}},
           {"energy_scale", -1.0},
           {"initial_energy", std::numeric_limits<double>::infinity()}}) {
    SolverSettings bad = good;
    bad[key] = value;
    EXPECT_NE(message(bad).find("/solver attribute " + key + " = "), std::string::npos)
        << message(bad);
    EXPECT_NE(message(bad).find("is out of range"), std::string::npos) << message(bad);
  }
  SolverSettings absent = good;
  absent.erase("flag");  // optional: the default stays
  EXPECT_EQ(message(absent), "no error");
}

TEST(ChangedSettings, ListsTheValuesARestartChanges) {
  const SolverSettings stored{{"cell_size", 1.0}, {"shape_function", std::string("gimp")}};
  const SolverSettings now{
      {"cell_size", 0.5}, {"shape_function", std::string("gimp")}, {"new_key", 1.0}};
  const auto changes = changed_settings(stored, now);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0], "cell_size 1 → 0.5");
}

TEST(OutputLock, ASecondRunIntoTheFolderIsRefusedNamingTheFirst) {
  Plan plan = plan_of(OutputSchedule(1.0, 0.25, {}, {}), "lock", true);  // a fresh folder
  const auto folder = plan.output.folder;
  std::filesystem::create_directories(folder);
  {
    const OutputLock first(folder);
    EXPECT_FALSE(first.took_over());
    try {
      const OutputLock second(folder);
      FAIL() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("another run (pid " + std::to_string(::getpid())),
                std::string::npos)
          << e.what();
    }
    // A run into a locked folder stops before it writes anything.
    RecordingStage stage(std::numeric_limits<double>::infinity(), StartOutput::none);
    EXPECT_THROW(execute(stage, plan, quiet), Error);
    EXPECT_FALSE(stage.opened_resumed.has_value());
  }
  EXPECT_FALSE(std::filesystem::exists(folder / ".slide-lock"));  // released
}

TEST(OutputLock, TheLockOfAGoneRunIsTakenOver) {
  const auto folder = scratch("stale-lock");
  std::filesystem::create_directories(folder);
  const std::string mark = this_process_mark();
  const std::string host = mark.substr(mark.rfind(' ') + 1);
  for (const std::string& stale :
       {std::string("999999999 12345 ") + host,     // a pid no process has
        std::to_string(::getpid()) + " 1 " + host,  // our pid, another start: reused
        std::string("garbage"), std::string()}) {   // damaged, empty
    std::ofstream(folder / ".slide-lock") << stale;
    EXPECT_FALSE(process_alive(stale)) << stale;
    const OutputLock lock(folder);
    EXPECT_TRUE(lock.took_over()) << stale;
  }
  EXPECT_TRUE(process_alive(mark));
}

TEST(CheckpointFileName, HasThreeDecimals) {
  EXPECT_EQ(checkpoint_file_name("fem", 2.0), "fem_t2.000.h5");
  EXPECT_EQ(checkpoint_file_name("mpm", 0.1 * 3), "mpm_t0.300.h5");
}

}  // namespace
}  // namespace slide::run
