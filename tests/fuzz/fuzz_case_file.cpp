// Fuzz driver of the case-file reader: the input is the text of a case.toml. It is read
// as every program reads it (parse_case), then checked as the programs check it before
// their first step: fem2mpm --case takes the [transfer] table (options_from), fem-solve
// builds the mesh and the FE model (run_fem, inputs only), mpm-solve fills the body with
// particles on its grid (run_mpm, pure MPM, inputs only). A case naming a Gmsh file is
// only parsed: the fuzzer's file names are not opened (fuzz_gmsh reads Gmsh files).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fem/fem_solver.hpp"
#include "mpm/mpm_run.hpp"
#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/inputs_only.hpp"
#include "transfer/transfer.hpp"

namespace {

using namespace slide;

void check_like_fem_solve(const Case& c) {
  fem::run_fem(fem::plan_fem(c, fuzz::fem_solve_inputs_only(), fuzz::quiet_logger()),
               fuzz::quiet_logger());
}

void check_like_mpm_solve(const Case& c) {
  mpm::run_mpm(mpm::plan_mpm(c, fuzz::mpm_solve_inputs_only(), fuzz::quiet_logger()),
               fuzz::quiet_logger());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // Relative file names of the case resolve in the scratch folder (where nothing is).
  const auto source = fuzz::scratch_folder() / "case.toml";
  Case c;
  if (!fuzz::accepts([&] { c = parse_case(text, source); })) return 0;
  const bool transfer_ok = fuzz::accepts([&] { (void)transfer::options_from(c.transfer); });
  if (c.mesh.generator == MeshGenerator::gmsh) return 0;
  const bool fem_ok = fuzz::accepts([&] { check_like_fem_solve(c); });
  const bool mpm_ok = fuzz::accepts([&] { check_like_mpm_solve(c); });
  fuzz::ensure_no_outputs("case file");
  if (transfer_ok && fem_ok && mpm_ok) fuzz::note_accepted();
  return 0;
}
