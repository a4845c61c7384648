// Fuzz driver of the OpenSees recorder reader (common/io/opensees_reader.hpp) and the
// import built on it (tools/interop/opensees_import.hpp): the input is a recorder text
// file. It stands in, in turn, for the displacement and for the stress recorder of the
// fixture case tests/fuzz/cases/fuzz-opensees (the elastic column of tests/tools/interop,
// whose other recorder files are the real ones), imported at the recorder times 0 and
// 0.02 s, with the reference state at 1 s; and it is read as a bare recorder file at t = 1.
#include <cstddef>
#include <cstdint>

#include "common/io/opensees_reader.hpp"
#include "tests/fuzz/fuzz_support.hpp"
#include "tools/interop/opensees_import.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slide;
  const Case& fixture = fuzz::fixture_case("fuzz-opensees");
  const auto input = fuzz::write_input({data, size}, "recorder.out");
  bool accepted = false;
  for (const bool as_stress : {false, true}) {
    Case c = fixture;
    (as_stress ? c.opensees->stress : c.opensees->displacement) = input;
    for (const double time : {0.0, 0.02}) {
      accepted = fuzz::accepts([&] { interop::import_opensees(c, time, nullptr); }) || accepted;
    }
  }
  fuzz::accepts([&] { read_recorder_row(input, 1.0, any_columns, "", RepeatedTime::first); });
  fuzz::ensure_no_outputs("opensees recorder");
  if (accepted) fuzz::note_accepted();
  return 0;
}
