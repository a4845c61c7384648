// Fuzz driver of the Gmsh reader: the input is a .msh file (ASCII 4.1 or 2.2). It stands
// in for the mesh file of the fixture case tests/fuzz/cases/fuzz-gmsh/case.toml (materials
// "soil" and "rock", boundaries "base" and "left"), which then goes through what the
// programs do with a case's mesh before their first step: fem-solve builds and validates
// the mesh, applies both stages' boundary tables and builds the FE model, for each of
// the three element types (a quad mesh read for tri3 is split); mpm-solve fills the body
// with particles on its grid (pure MPM, quad4 and tri3 meshes). All of it through run_fem and
// run_mpm with inputs_only, the programs' own code.
#include <array>
#include <cstddef>
#include <cstdint>

#include "fem/fem_solver.hpp"
#include "mpm/mpm_run.hpp"
#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/inputs_only.hpp"

namespace {

using namespace slide;

void check_like_fem_solve(const Case& c, ElementType type) {
  fem::FemOptions options = fuzz::fem_solve_inputs_only();
  options.element = type;
  fem::run_fem(fem::plan_fem(c, options, fuzz::quiet_logger()), fuzz::quiet_logger());
}

void check_like_mpm_solve(const Case& c) {
  mpm::run_mpm(mpm::plan_mpm(c, fuzz::mpm_solve_inputs_only(), fuzz::quiet_logger()),
               fuzz::quiet_logger());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Case c = fuzz::fixture_case("fuzz-gmsh");
  c.mesh.gmsh_file = fuzz::write_input({data, size}, "mesh.msh");
  // A valid mesh serves tri3 and, when it has quads only, the quad types too.
  bool fem_ok = false, mpm_ok = false;
  for (const ElementType type :
       {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3}) {
    fem_ok = fuzz::accepts([&] { check_like_fem_solve(c, type); }) || fem_ok;
  }
  for (const ElementType type : {ElementType::quad4_1gp, ElementType::tri3}) {
    c.mesh.element_type = type;
    mpm_ok = fuzz::accepts([&] { check_like_mpm_solve(c); }) || mpm_ok;
  }
  fuzz::ensure_no_outputs("gmsh");
  if (fem_ok && mpm_ok) fuzz::note_accepted();
  return 0;
}
