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

int main(int argc, char** argv) {
  using namespace slide;
  // MPI build: the ranks of `mpirun -np N mpm-solve …` (docs/parallel.md); one otherwise.
  const RankSession session(argc, argv);
  CLI::App app{"mpm-solve: material point runout phase (sequential hybrid FEM → MPM)", "mpm-solve"};
  std::string case_file, output_dir, particles, restart, shape, scheme;
  double until = 0.0, vtk_every = 0.0;
  int threads = 0;
  bool quiet = false, no_vtk = false;
  app.add_option("case", case_file, "case file (case.toml)")->required();
  app.add_option("-o,--output", output_dir, "output folder")->required();
  app.add_option("--particles", particles, "particle file to start from (fem2mpm output)");
  app.add_option("--until", until, "stop at this time (s) instead of the case's end time");
  app.add_option("--restart", restart, "continue from an mpm checkpoint (mpm_t<T>.h5)");
  app.add_option("--threads", threads,
                 "OpenMP threads (default: all cores; under mpirun, the cores over the ranks "
                 "on the machine)")
      ->check(positive_number());
  app.add_option("--shape-function", shape, "override the case: gimp or linear")
      ->check(CLI::IsMember({"gimp", "linear"}));
  app.add_option("--update-scheme", scheme, "override the case: musl or usl")
      ->check(CLI::IsMember({"musl", "usl"}));
  app.add_flag("--no-vtk", no_vtk, "write no VTK files");
  app.add_option("--vtk-every", vtk_every,
                 "VTK frames every this many seconds, a multiple of mpm.output_every (0: every "
                 "output step; default: mpm.vtk_every, else about 100 frames a run)")
      ->check(non_negative_number());
  bool other_case = false;
  app.add_flag("--other-case", other_case,
               "accept a --particles or --restart file written for another case (warns)");
  app.add_flag("-q,--quiet", quiet, "print warnings, errors and the summary line only");
  if (const auto status = parse_command_line(app, argc, argv)) return *status;

  return run_main_on_ranks("mpm-solve", [&] {
    const Ranks& ranks = Ranks::world();
    // Ranks on one machine share its cores: by default each takes its share of them.
    if (threads == 0 && ranks.on_this_machine() > 1)
      threads = std::max(1, omp_get_num_procs() / ranks.on_this_machine());
    if (threads > 0) omp_set_num_threads(threads);
    const Logger log("mpm-solve", quiet, !ranks.root());
    const Case c = load_case(case_file);
    mpm::RunOptions options;
    options.output_dir = output_dir;
    if (!particles.empty()) options.particles_file = particles;
    if (!restart.empty()) options.restart_file = restart;
    if (app.count("--until") > 0) options.until = until;
    options.write_vtk = !no_vtk;
    options.other_case = other_case;
    if (app.count("--vtk-every") > 0) options.vtk_every = vtk_every;
    if (!shape.empty())
      options.shape_function = shape == "gimp" ? ShapeFunction::gimp : ShapeFunction::linear;
    if (!scheme.empty())
      options.update_scheme = scheme == "musl" ? UpdateScheme::musl : UpdateScheme::usl;
    mpm::run_mpm(mpm::plan_mpm(c, options), log);  // ends with the summary line
  });
}
