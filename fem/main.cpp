// fem-solve: the finite element phase of a landslide (docs/method.md §3).
//
// Stage 1 solves the elastic geostatic equilibrium of the case's mesh under gravity
// (one sparse linear solve) and writes it as the t = 0 checkpoint; stage 2 switches to
// the materials' plastic models, releases the boundaries the case releases and
// integrates the dynamics explicitly to the end time, writing checkpoints, the history
// of energy and mesh quality, and VTK frames. Plane strain, SI units.
//
//   fem-solve cases/column-short/case.toml -o cases/column-short/out/fem
//   fem-solve cases/column-short/case.toml -o out/fem --restart out/fem/fem_t4.000.h5
//   fem-solve cases/slope-frictional/case.toml -o out/fos --strength-reduction
#include <string>

#include <CLI/CLI.hpp>

#include "common/base/log.hpp"
#include "common/base/program.hpp"
#include "common/geometry/element.hpp"
#include "common/input/case_file.hpp"
#include "fem/fem_plan.hpp"
#include "fem/fem_solver.hpp"
#include "fem/strength_reduction.hpp"

namespace {

using namespace slide;

/// The command line as given (what needs no conversion goes to the options directly).
struct CommandLine {
  std::string case_file, element, kinematics, restart;
  fem::FemOptions options;
  double until = 0.0, vtk_every = 0.0;
  bool quiet = false, no_vtk = false, no_disk_check = false, strength_reduction = false;
  std::string tag;
};

void add_options(CLI::App& app, CommandLine& c) {
  app.add_option("case", c.case_file, "case file (case.toml)")->required();
  app.add_option("-o,--output", c.options.output_dir, "output folder")
      ->required()
      ->type_name("DIR");
  app.add_option("--until", c.until, "end time in s (instead of fem.end_time)");
  app.add_option("--restart", c.restart, "continue from this kind \"fem\" checkpoint")
      ->type_name("FILE");
  app.add_option("--checkpoint-every", c.options.checkpoint_every,
                 "also write a checkpoint every DT s");
  app.add_flag("--checkpoint-at-zone-exit", c.options.checkpoint_at_zone_exit,
               "write a checkpoint of the last output state inside the recommended transfer zone");
  app.add_option("--element", c.element, "element type instead of mesh.element")
      ->check(CLI::IsMember({"quad4-1gp", "quad4-2x2", "tri3"}));
  app.add_option("--kinematics", c.kinematics, "kinematics instead of fem.kinematics")
      ->check(CLI::IsMember({"small-strain", "updated-lagrangian"}));
  app.add_flag("--no-vtk", c.no_vtk, "write no VTK files");
  app.add_flag("--no-disk-check", c.no_disk_check,
               "start even when the outputs, estimated, would not fit on the disk");
  app.add_option("--vtk-every", c.vtk_every,
                 "VTK frames every this many seconds, a multiple of fem.output_every (0: every "
                 "output step; default: fem.vtk_every, else about 100 frames a run)")
      ->check(non_negative_number());
  app.add_option("--allow-changed", c.options.allow_changed,
                 "with --restart: a part of the case that may differ from the checkpoint's "
                 "(materials, gravity, mesh, boundaries, damping, time_step, motion, recorders)");
  app.add_flag("--strength-reduction", c.strength_reduction,
               "instead of the failure stage: the factor of safety by strength reduction "
               "(tan φ and c divided by F, bisection on F; OUTPUT/strength_reduction.txt)");
  app.add_flag("-q,--quiet", c.quiet, "print only warnings, errors and the summary line");
  app.add_option("--tag", c.tag,
                 "a name for this run on every line it prints, e.g. tt2: \"mpm-solve[tt2]: ...\" "
                 "(the case pipeline passes the run's folder name)");
}

fem::FemOptions options_of(const CLI::App& app, const CommandLine& c) {
  fem::FemOptions options = c.options;
  if (app.count("--until") > 0) options.until = c.until;
  if (!c.restart.empty()) options.restart = c.restart;
  if (!c.element.empty()) options.element = parse_element_type(c.element, "--element");
  if (!c.kinematics.empty()) {
    options.kinematics = c.kinematics == "updated-lagrangian" ? Kinematics::updated_lagrangian
                                                              : Kinematics::small_strain;
  }
  options.write_vtk = !c.no_vtk;
  options.disk_check = !c.no_disk_check;
  if (app.count("--vtk-every") > 0) options.vtk_every = c.vtk_every;
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  prefer_yielding_threads(argv);
  CLI::App app{
      "fem-solve: the finite element phase (geostatic stage, failure stage, mesh "
      "quality, checkpoints)",
      "fem-solve"};
  CommandLine command;
  add_options(app, command);
  if (const auto status = parse_command_line(app, argc, argv)) return *status;

  return run_main("fem-solve", [&] {
    Logger logger("fem-solve", command.quiet);
    logger.set_tag(command.tag);
    const Case c = load_case(command.case_file);
    if (command.strength_reduction) {
      const auto r = fem::run_strength_reduction(c, options_of(app, command), logger);
      logger.result("summary: factor_of_safety={:.4f} failing_factor={:.4f} trials={}",
                    r.factor_of_safety, r.failing_factor, r.trials.size());
      return;
    }
    fem::run_fem(fem::plan_fem(c, options_of(app, command), logger),
                 logger);  // ends with the summary
  });
}
