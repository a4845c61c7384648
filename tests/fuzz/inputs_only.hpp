// The options under which the drivers run fem-solve's and mpm-solve's own code: every
// read and check the program makes, then a return before its first output (the
// `inputs_only` of fem/fem_solver.hpp and mpm/mpm_run.hpp), with the output folder the
// drivers check stays empty (fuzz_support.hpp, ensure_no_outputs). A driver sets what
// its input stands for (a restart file, a particle file, an element type) on top.
#pragma once

#include "fem/fem_solver.hpp"
#include "mpm/mpm_run.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace slide::fuzz {

inline fem::FemOptions fem_solve_inputs_only() {
  fem::FemOptions options;
  options.output_dir = output_folder();
  options.write_vtk = false;
  options.inputs_only = true;
  return options;
}

inline mpm::RunOptions mpm_solve_inputs_only() {
  mpm::RunOptions options;
  options.output_dir = output_folder();
  options.write_vtk = false;
  options.inputs_only = true;
  return options;
}

}  // namespace slide::fuzz
