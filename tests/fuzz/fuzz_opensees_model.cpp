// Fuzz driver of the OpenSees model reader (common/io/opensees_reader.hpp): the input is
// a `print -JSON` model. It stands in for the model of the fixture case
// tests/fuzz/cases/fuzz-opensees (the elastic column of tests/tools/interop), which then
// goes through what fem-solve does with a case's mesh before its first step (run_fem
// with inputs_only: the mesh built and validated, the boundary tables applied, the FE
// model built) and through opensees2fem's import with the column's recorder files.
#include <cstddef>
#include <cstdint>

#include "fem/fem_solver.hpp"
#include "tests/fuzz/fuzz_support.hpp"
#include "tests/fuzz/inputs_only.hpp"
#include "tools/interop/opensees_import.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slide;
  Case c = fuzz::fixture_case("fuzz-opensees");
  c.mesh.opensees_file = fuzz::write_input({data, size}, "model.json");
  const bool fem_ok = fuzz::accepts([&] {
    fem::run_fem(fem::plan_fem(c, fuzz::fem_solve_inputs_only(), fuzz::quiet_logger()),
                 fuzz::quiet_logger());
  });
  const bool import_ok = fuzz::accepts([&] { interop::import_opensees(c, 0.0, nullptr); });
  fuzz::ensure_no_outputs("opensees model");
  if (fem_ok && import_ok) fuzz::note_accepted();
  return 0;
}
