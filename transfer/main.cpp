// fem2mpm: turns the FE model at the transfer time t_T into material points
// (docs/method.md §4). Reads one FE checkpoint, writes the particle file mpm-solve starts
// from, and prints and writes the transfer report (PARTICLES.transfer.json).
//
//   fem2mpm out/fem/fem_t2.000.h5 -o out/tt2/particles.h5 --particles-per-element 4
//
// Settings come from the built-in defaults, then the case's [transfer] table (--case),
// then the command line.
#include <filesystem>

#include <CLI/CLI.hpp>

#include "common/base/error.hpp"
#include "common/base/log.hpp"
#include "common/base/program.hpp"
#include "common/input/case_file.hpp"
#include "common/io/atomic_file.hpp"
#include "common/io/checkpoint.hpp"
#include "transfer/transfer.hpp"

namespace {

using namespace slide;

struct CommandLine {
  std::string input;
  std::string output;
  std::string particles_per_element;
  std::string stress_interpolation;
  std::string rbf_polynomial;
  double rbf_shape = 0.0;
  int rbf_neighbours = 0;
  bool allow_inverted = false;
  double collapsed_volume_ratio = 0.0;
  std::string case_file;
  std::vector<std::string> assume_liquefied;
  std::string correlation;
  bool quiet = false;
  std::string tag;
};

transfer::TransferOptions options_for(const CommandLine& line, const CLI::App& app) {
  transfer::TransferOptions options;
  if (!line.case_file.empty()) options = transfer::options_from(load_case(line.case_file).transfer);
  if (app.count("--particles-per-element") > 0) {
    options.particles = transfer::parse_particles_per_element(line.particles_per_element,
                                                              "--particles-per-element");
  }
  if (app.count("--stress-interpolation") > 0) {
    options.stress_interpolation = line.stress_interpolation == "rbf" ? StressInterpolation::rbf
                                   : line.stress_interpolation == "rbf-local"
                                       ? StressInterpolation::rbf_local
                                       : StressInterpolation::element;
  }
  if (app.count("--rbf-polynomial") > 0) {
    options.rbf_polynomial =
        line.rbf_polynomial == "linear" ? RbfPolynomial::linear : RbfPolynomial::none;
  }
  if (app.count("--rbf-shape") > 0) options.rbf_shape = line.rbf_shape;
  if (app.count("--rbf-neighbours") > 0) options.rbf_neighbours = line.rbf_neighbours;
  options.allow_inverted = line.allow_inverted;
  if (app.count("--collapsed-volume-ratio") > 0) {
    options.collapsed_volume_ratio = line.collapsed_volume_ratio;
  }
  options.assume_liquefied = line.assume_liquefied;
  if (app.count("--correlation") > 0) {
    options.correlation = parse_residual_strength_correlation(line.correlation, "--correlation");
  }
  return options;
}

void run(const CommandLine& line, const CLI::App& app) {
  Logger logger("fem2mpm", line.quiet);
  logger.set_tag(line.tag);
  std::error_code same_error;
  if (std::filesystem::equivalent(line.input, line.output, same_error)) {
    throw Error("-o {}: is the FE checkpoint being read; write the particles to another file",
                line.output);
  }
  const std::filesystem::path folder = std::filesystem::path(line.output).parent_path();
  const std::size_t removed = remove_stale_temporaries(folder.empty() ? "." : folder);
  if (removed > 0) logger.info("removed {} temporary file(s) that killed runs left", removed);
  const transfer::TransferOptions options = options_for(line, app);
  const FemCheckpoint fem = read_fem_checkpoint(line.input);
  logger.info("read {} (t = {} s, case \"{}\")", line.input, fem.header.time, fem.header.case_name);
  transfer::TransferResult result = transfer::transfer(fem, options, &logger);
  result.report.input = line.input;
  result.report.output = line.output;
  for (const auto& text : transfer::report_warnings(result.report)) logger.warning("{}", text);
  // The report goes with its particle file: a particle file never stands beside the
  // report of another run (write_pair_atomically; a kill between the two renames leaves
  // the report alone, and the missing particle file makes a pipeline rerun fem2mpm).
  const auto json = transfer::report_path(line.output);
  write_pair_atomically(
      json,
      [&](const std::filesystem::path& temporary) {
        write_text_atomically(temporary, transfer::report_json(result.report));
      },
      line.output,
      [&](const std::filesystem::path& temporary) {
        write_checkpoint(temporary, result.particles);
      });
  for (const auto& text : transfer::format_report_lines(result.report)) logger.info("{}", text);
  logger.info("wrote {} and {}", line.output, json.string());
}

}  // namespace

int main(int argc, char** argv) {
  prefer_yielding_threads(argv);
  CLI::App app(
      "fem2mpm: converts an FE checkpoint at the transfer time into material points "
      "(positions, velocities, stresses, state, masses, volumes) for mpm-solve",
      "fem2mpm");
  CommandLine line;
  app.add_option("fem_checkpoint", line.input, "FE checkpoint (kind \"fem\")")->required();
  app.add_option("-o,--output", line.output, "particle file to write (HDF5)")
      ->required()
      ->type_name("FILE");
  app.add_option("--particles-per-element", line.particles_per_element,
                 "N (N×N per quad, N per triangle) or NxM; default 4 (triangles: 16)");
  app.add_option("--stress-interpolation", line.stress_interpolation,
                 "Gauss-point fields: rbf (global multiquadric, default), rbf-local (k nearest "
                 "Gauss points) or element (the element's own Gauss value)")
      ->check(CLI::IsMember({"rbf", "rbf-local", "element"}));
  app.add_option("--rbf-shape", line.rbf_shape,
                 "multiquadric shape parameter c in m (default sqrt(A_box/N_g))")
      ->check(positive_number());
  app.add_option("--rbf-polynomial", line.rbf_polynomial,
                 "none or linear (exact for linear fields); default none for rbf, linear for "
                 "rbf-local")
      ->check(CLI::IsMember({"none", "linear"}));
  app.add_option(
         "--rbf-neighbours", line.rbf_neighbours,
         "k of rbf-local (default " + std::to_string(transfer::default_rbf_neighbours) + ")")
      ->check(positive_number());
  app.add_flag("--allow-inverted", line.allow_inverted,
               "transfer inverted elements (with their reference volume) instead of stopping");
  app.add_option("--collapsed-volume-ratio", line.collapsed_volume_ratio,
                 "elements with V_t/V_0 below this (and inverted ones) give no RBF centre; "
                 "0: only inverted ones (default " +
                     fmt::format("{:g}", transfer::default_collapsed_volume_ratio) + ")")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--assume-liquefied", line.assume_liquefied,
                 "materials whose every particle is taken as liquefied, whatever its r_u,max "
                 "(a zone known to have liquefied)")
      ->delimiter(',');
  app.add_option("--correlation", line.correlation,
                 "residual-strength correlation for every material with a liquefaction rule: "
                 "idriss-boulanger-void-redistribution, idriss-boulanger, olson-stark, ratio, "
                 "none (default: each material's own)");
  app.add_option("--case", line.case_file, "case file whose [transfer] table gives the defaults");
  app.add_flag("-q,--quiet", line.quiet, "print nothing but errors and warnings");
  app.add_option("--tag", line.tag,
                 "a name for this run on every line it prints, e.g. tt2: \"mpm-solve[tt2]: ...\" "
                 "(the case pipeline passes the run's folder name)");
  if (const auto status = parse_command_line(app, argc, argv)) return *status;
  return run_main("fem2mpm", [&] { run(line, app); });
}
