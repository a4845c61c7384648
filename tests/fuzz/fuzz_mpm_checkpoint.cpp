// Fuzz driver of the MPM checkpoint reader: the input is a kind "mpm" HDF5 file
// (mpm-solve's mpm_t<T>.h5 or mpm_final.h5), written to the scratch folder and read by
// path as `mpm-solve CASE --restart FILE` reads it: read_particle_checkpoint, the checks
// against the fixture case (name, materials), every /solver counter and reference
// (read_mpm_record), the particles' validation on the case's grid, the solver's
// construction with the stored clock, the comparison of the stored settings and the
// first time step (run_mpm with inputs_only).
// The fixture is tests/fuzz/cases/fuzz-checkpoints/case.toml, the case the seeds come from.
#include <cstddef>
#include <cstdint>

#include "mpm/mpm_run.hpp"
#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/inputs_only.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slide;
  const Case& c = fuzz::fixture_case("fuzz-checkpoints");
  mpm::RunOptions options = fuzz::mpm_solve_inputs_only();
  options.restart = fuzz::write_input({data, size}, "mpm.h5");
  const bool accepted = fuzz::accepts(
      [&] { mpm::run_mpm(mpm::plan_mpm(c, options, fuzz::quiet_logger()), fuzz::quiet_logger()); });
  fuzz::finish_hdf5_input("mpm-solve --restart");
  fuzz::ensure_no_outputs("mpm-solve --restart");
  if (accepted) fuzz::note_accepted();
  return 0;
}
