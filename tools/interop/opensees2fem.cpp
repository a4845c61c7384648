// opensees2fem: an OpenSees model and its recorders at one time → an FE checkpoint that
// fem2mpm and mpm-solve run from (tools/interop/README.md).
//
//   opensees2fem case.toml -o out/fem --time 2.0
//
// writes out/fem/fem_t<T>.h5, T the recorder time minus opensees.reference_time, the
// name fem-solve gives the same state, so the case's Make pipeline runs on from it.
#include <filesystem>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/base/error.hpp"
#include "common/base/log.hpp"
#include "common/base/program.hpp"
#include "common/input/case_file.hpp"
#include "common/io/atomic_file.hpp"
#include "common/io/checkpoint.hpp"
#include "common/run/stage.hpp"
#include "tools/interop/opensees_import.hpp"

namespace {

using namespace slide;

struct CommandLine {
  std::string case_file;
  std::string output;
  std::vector<double> times;
  bool quiet = false;
};

void import_times(const CommandLine& line) {
  const Logger logger("opensees2fem", line.quiet);
  const Case c = load_case(line.case_file);
  const std::filesystem::path folder = line.output;
  std::error_code ec;
  if (std::filesystem::exists(folder, ec) && !std::filesystem::is_directory(folder, ec)) {
    throw Error("-o {}: is a file; expected the folder to write fem_t<T>.h5 into", line.output);
  }
  // Two different times whose files would share a name (three decimals): the second
  // would replace the first. The names are of the times on the project's clock.
  if (c.opensees) {
    std::vector<double> times;
    for (const double time : line.times) times.push_back(time - c.opensees->start_time);
    run::check_checkpoint_times(times, "fem", "--time");
  }
  // Every state is imported before the first file is written: a bad time or recorder
  // leaves the folder as it was.
  std::vector<FemCheckpoint> checkpoints;
  for (const double time : line.times)
    checkpoints.push_back(interop::import_opensees(c, time, &logger));
  std::filesystem::create_directories(folder);
  const std::size_t removed = remove_stale_temporaries(folder);
  if (removed > 0) logger.info("removed {} temporary file(s) that killed runs left", removed);
  for (const FemCheckpoint& checkpoint : checkpoints) {
    const std::filesystem::path file =
        folder / run::checkpoint_file_name("fem", checkpoint.header.time);
    write_checkpoint(file, checkpoint);
    logger.info("wrote {} (t = {} s: {} nodes, {} elements, {} Gauss points)", file.string(),
                checkpoint.header.time, checkpoint.mesh.node_count(),
                checkpoint.mesh.element_count(), checkpoint.stress.size());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "opensees2fem: imports a 2D OpenSees model (print -JSON) and its recorder output at "
      "one time as an FE checkpoint for fem2mpm (tools/interop/README.md)",
      "opensees2fem");
  CommandLine line;
  app.add_option("case", line.case_file,
                 "case file with mesh.generator = \"opensees\" and an [opensees] table")
      ->required();
  app.add_option("-o,--output", line.output, "folder to write fem_t<T>.h5 into")
      ->required()
      ->type_name("DIR");
  app.add_option("-t,--time", line.times,
                 "recorder time(s) to import, s on OpenSees's clock (repeat for several)")
      ->required();
  app.add_flag("-q,--quiet", line.quiet, "print nothing but errors and warnings");
  if (const auto status = parse_command_line(app, argc, argv)) return *status;
  return run_main("opensees2fem", [&] { import_times(line); });
}
