// mpm2cbgeo: particles (a fem2mpm particle file or an mpm-solve checkpoint) → the input
// of a CB-Geo MPM run from the same state on the same grid (tools/interop/README.md).
//
//   mpm2cbgeo case.toml out/tt0/particles.h5 -o out/cbgeo-tt0
//   mpm -f out/cbgeo-tt0/ -i mpm.json        # CB-Geo MPM
#include <filesystem>

#include <CLI/CLI.hpp>

#include "common/base/error.hpp"
#include "common/base/log.hpp"
#include "common/base/program.hpp"
#include "common/input/case_file.hpp"
#include "common/io/atomic_file.hpp"
#include "common/io/checkpoint.hpp"
#include "tools/interop/cbgeo_export.hpp"

namespace {

using namespace slide;

struct CommandLine {
  std::string case_file;
  std::string particles;
  std::string output;
  interop::CbGeoExportOptions options;
  bool other_case = false;
  bool quiet = false;
};

/// The particles of this case (or --other-case), as mpm-solve takes them: the file's
/// attribute `case` names the case that made it.
void check_case_name(const CommandLine& line, const Case& c, const Logger& logger) {
  const CheckpointHeader header = read_checkpoint_header(line.particles);
  if (header.case_name == c.name) return;
  if (!line.other_case) {
    throw Error(
        "{}: written for case \"{}\", not for case \"{}\" of {} (--other-case to export it "
        "anyway)",
        line.particles, header.case_name, c.name, line.case_file);
  }
  logger.warning("{}: written for case \"{}\", exported with case \"{}\" (--other-case)",
                 line.particles, header.case_name, c.name);
}

void export_particles(const CommandLine& line) {
  const Logger logger("mpm2cbgeo", line.quiet);
  const Case c = load_case(line.case_file);
  check_case_name(line, c, logger);
  const ParticleCheckpoint checkpoint = read_particle_checkpoint(line.particles);
  logger.info("read {}: {} particles at t = {} s ({})", line.particles,
              checkpoint.particles.count(), checkpoint.header.time, checkpoint.header.producer);
  const interop::CbGeoInput input = interop::export_cbgeo(c, checkpoint, line.options);
  const std::filesystem::path folder = line.output;
  std::error_code ec;
  if (std::filesystem::exists(folder, ec) && !std::filesystem::is_directory(folder, ec)) {
    throw Error("-o {}: is a file; expected the folder of the CB-Geo input", line.output);
  }
  std::filesystem::create_directories(folder);
  remove_stale_temporaries(folder);
  for (const auto& [name, text] : input.files) write_text_atomically(folder / name, text);
  interop::write_cbgeo_particles(folder / input.resume_file, input.resume_particles);
  for (const auto& note : input.notes) logger.info("not carried over: {}", note);
  logger.info("wrote {} files to {}: dt = {:.6g} s, {} steps", input.files.size(), folder.string(),
              input.time_step, input.steps);
  logger.info("run it with CB-Geo MPM: mpm -f {}/ -i mpm.json", folder.string());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "mpm2cbgeo: writes the input of a CB-Geo MPM run (mesh, particles, stresses, volumes, "
      "entity sets, mpm.json) from a particle file or an mpm checkpoint (tools/interop/README.md)",
      "mpm2cbgeo");
  CommandLine line;
  app.add_option("case", line.case_file, "the case file (grid, boundaries, MPM settings)")
      ->required();
  app.add_option("particles", line.particles, "particle file (fem2mpm) or mpm checkpoint")
      ->required();
  app.add_option("-o,--output", line.output, "folder to write the CB-Geo input into")
      ->required()
      ->type_name("DIR");
  app.add_option("--end-time", line.options.end_time,
                 "end time in s on the project's clock (default: the case's mpm.end_time)")
      ->check(positive_number());
  app.add_option("--output-every", line.options.output_every,
                 "s between CB-Geo's HDF5 outputs (default: the case's mpm.checkpoint_every)")
      ->check(positive_number());
  app.add_option("--courant", line.options.courant,
                 "Courant number of CB-Geo's fixed step, at the particles' present density "
                 "(default 0.05: the step must hold while the front's particles expand)")
      ->check(positive_number())
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--scheme", line.options.scheme,
                 "CB-Geo's update scheme: usl (default, the nearest to MUSL) or usf")
      ->check(CLI::IsMember({"usl", "usf"}));
  app.add_flag("--other-case", line.other_case,
               "export a file that another case made, on this case's grid and settings");
  app.add_flag("-q,--quiet", line.quiet, "print nothing but errors and warnings");
  if (const auto status = parse_command_line(app, argc, argv)) return *status;
  return run_main("mpm2cbgeo", [&] { export_particles(line); });
}
