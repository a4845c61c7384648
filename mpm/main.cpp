// mpm-solve: the material point runout phase (docs/method.md §5).
//
// Continues a body of material points under gravity on a background grid of square
// cells until the end time (or rest): explicit MPM, uGIMP or linear shape functions,
// USL or MUSL, FLIP with an optional PIC share or APIC, Mohr–Coulomb or linear elastic
// particles, Coulomb base friction, local damping. Plane strain, SI units.
//
//   mpm-solve cases/column-short/case.toml -o out/tt2 --particles out/particles_t2.h5
//   mpm-solve cases/column-short/case.toml -o out/pure-mpm              (pure MPM)
//   mpm-solve cases/column-short/case.toml -o out/pure-mpm --restart out/pure-mpm/mpm_t10.000.h5
//
// Writes OUT/mpm_t<T>.h5 checkpoints, OUT/mpm_final.h5, OUT/mpm_history.csv, VTK files,
// and the summary line `summary: steps=… particles=… wall_s=… particle_steps_per_s=…`.
#include <algorithm>

#include <omp.h>

#include "common/base/error.hpp"
#include "common/base/log.hpp"
#include "common/base/program.hpp"
#include "common/base/ranks.hpp"
#include "common/input/case_file.hpp"
#include "mpm/mpm_plan.hpp"
#include "mpm/mpm_run.hpp"

namespace {

using namespace slide;

/// The command line as given.
struct CommandLine {
  std::string case_file, output_dir, particles, restart, shape, scheme;
  double until = 0.0, vtk_every = 0.0;
  int threads = 0;
  bool quiet = false, no_vtk = false, no_disk_check = false, other_case = false;
  std::string tag;
  std::vector<std::string> allow_changed;
};

void add_options(CLI::App& app, CommandLine& c) {
  app.add_option("case", c.case_file, "case file (case.toml)")->required();
  app.add_option("-o,--output", c.output_dir, "output folder")->required()->type_name("DIR");
  app.add_option("--particles", c.particles, "particle file to start from (fem2mpm output)")
      ->type_name("FILE");
  app.add_option("--until", c.until, "stop at this time (s) instead of the case's end time");
  app.add_option("--restart", c.restart, "continue from an mpm checkpoint (mpm_t<T>.h5)")
      ->type_name("FILE");
  app.add_option("--threads", c.threads,
                 "OpenMP threads (default: all cores; under mpirun, the cores over the ranks "
                 "on the machine)")
      ->check(positive_number());
  app.add_option("--shape-function", c.shape, "override the case: gimp or linear")
      ->check(CLI::IsMember({"gimp", "linear"}));
  app.add_option("--update-scheme", c.scheme, "override the case: musl or usl")
      ->check(CLI::IsMember({"musl", "usl"}));
  app.add_flag("--no-vtk", c.no_vtk, "write no VTK files");
  app.add_flag("--no-disk-check", c.no_disk_check,
               "start even when the outputs, estimated, would not fit on the disk");
  app.add_option("--vtk-every", c.vtk_every,
                 "VTK frames every this many seconds, a multiple of mpm.output_every (0: every "
                 "output step; default: mpm.vtk_every, else about 100 frames a run)")
      ->check(non_negative_number());
  app.add_flag("--other-case", c.other_case,
               "accept a --particles or --restart file written for another case (warns)");
  app.add_option("--allow-changed", c.allow_changed,
                 "with --restart: a part of the case that may differ from the checkpoint's "
                 "(materials, gravity, grid, algorithms, boundaries, damping, time_step, rest; "
                 "pure MPM: mesh, start, motion)");
  app.add_flag("-q,--quiet", c.quiet, "print warnings, errors and the summary line only");
  app.add_option("--tag", c.tag,
                 "a name for this run on every line it prints, e.g. tt2: \"mpm-solve[tt2]: ...\" "
                 "(the case pipeline passes the run's folder name)");
}

mpm::RunOptions options_of(const CLI::App& app, const CommandLine& c) {
  mpm::RunOptions options;
  options.output_dir = c.output_dir;
  if (!c.particles.empty()) options.particles_file = c.particles;
  if (!c.restart.empty()) options.restart = c.restart;
  if (app.count("--until") > 0) options.until = c.until;
  options.write_vtk = !c.no_vtk;
  options.disk_check = !c.no_disk_check;
  options.other_case = c.other_case;
  options.allow_changed = c.allow_changed;
  if (app.count("--vtk-every") > 0) options.vtk_every = c.vtk_every;
  if (!c.shape.empty())
    options.shape_function = c.shape == "gimp" ? ShapeFunction::gimp : ShapeFunction::linear;
  if (!c.scheme.empty())
    options.update_scheme = c.scheme == "musl" ? UpdateScheme::musl : UpdateScheme::usl;
  return options;
}

}  // namespace

int main(int argc, char** argv) {
  prefer_yielding_threads(argv);
  // MPI build: the ranks of `mpirun -np N mpm-solve …` (docs/parallel.md); one otherwise.
  const RankSession session(argc, argv);
  CLI::App app{"mpm-solve: material point runout phase (sequential hybrid FEM → MPM)", "mpm-solve"};
  CommandLine command;
  add_options(app, command);
  if (const auto status = parse_command_line(app, argc, argv)) return *status;

  return run_main_on_ranks("mpm-solve", [&] {
    const Ranks& ranks = Ranks::world();
    // Ranks on one machine share its cores: by default each takes its share of them.
    int threads = command.threads;
    if (threads == 0 && ranks.on_this_machine() > 1)
      threads = std::max(1, omp_get_num_procs() / ranks.on_this_machine());
    if (threads > 0) omp_set_num_threads(threads);
    Logger log("mpm-solve", command.quiet, !ranks.root());
    log.set_tag(command.tag);
    const Case c = load_case(command.case_file);
    mpm::run_mpm(mpm::plan_mpm(c, options_of(app, command), log),
                 log);  // ends with the summary line
  });
}
