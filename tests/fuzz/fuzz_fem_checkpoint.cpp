// Fuzz driver of the FE checkpoint reader: the input is a kind "fem" HDF5 file, written
// to the scratch folder and read by path. It goes through both programs that read such
// files, as far as they go before writing anything:
//  - fem2mpm --case: read_fem_checkpoint, then the whole transfer in memory with the
//    fixture case's [transfer] table (the file's own checks, particle placement, RBF);
//  - fem-solve --restart (with --element of the file's element type): the header, the
//    checkpoint, the checks against the fixture case (name, materials, stage, time),
//    the mesh validation, both boundary tables, the FE model and the state from the
//    checkpoint (run_fem with inputs_only).
// The fixture is tests/fuzz/cases/fuzz-checkpoints/case.toml, the case the seeds come from.
#include <cstddef>
#include <cstdint>

#include "common/input/case_fingerprint.hpp"
#include "common/io/checkpoint.hpp"
#include "fem/fem_solver.hpp"
#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/inputs_only.hpp"
#include "transfer/transfer.hpp"

namespace {

using namespace slide;

void check_like_fem2mpm(const FemCheckpoint& checkpoint, const Case& c) {
  (void)transfer::transfer(checkpoint, transfer::options_from(c.transfer), nullptr);
}

void check_like_fem_solve_restart(const std::filesystem::path& file, const Case& c,
                                  ElementType element) {
  fem::FemOptions options = fuzz::fem_solve_inputs_only();
  options.restart = file;
  options.element = element;
  // The seeds were written with other kinematics and elements: this driver reads files,
  // the case's comparison with them has tests of its own.
  options.allow_changed = fingerprint_parts(fem_fingerprint(c));
  fem::run_fem(fem::plan_fem(c, options, fuzz::quiet_logger()), fuzz::quiet_logger());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Case& c = fuzz::fixture_case("fuzz-checkpoints");
  const auto file = fuzz::write_input({data, size}, "fem.h5");
  FemCheckpoint checkpoint;
  const bool read_ok = fuzz::accepts([&] { checkpoint = read_fem_checkpoint(file); });
  if (!read_ok) {
    fuzz::finish_hdf5_input("read_fem_checkpoint");
    return 0;
  }
  fuzz::ensure_hdf5_closed("read_fem_checkpoint");
  const bool transfer_ok = fuzz::accepts([&] { check_like_fem2mpm(checkpoint, c); });
  const bool restart_ok =
      fuzz::accepts([&] { check_like_fem_solve_restart(file, c, checkpoint.mesh.element_type); });
  fuzz::finish_hdf5_input("fem-solve --restart");
  fuzz::ensure_no_outputs("fem-solve --restart");
  if (transfer_ok && restart_ok) fuzz::note_accepted();
  return 0;
}
