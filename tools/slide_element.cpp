// slide-element: single-point tests of a soil model (common/physics/element_test.hpp),
// for checking a material before it goes into a slope, and PM4Sand's calibration.
//
//   slide-element cyclic    OUT.csv   undrained cyclic simple shear at a CSR
//   slide-element monotonic OUT.csv   drained or undrained monotonic simple shear
//   slide-element cyclic-strain OUT.csv  undrained cyclic simple shear at a strain amplitude
//   slide-element calibrate OUT_DIR   h_po for a target CRR at 15 cycles, and the CRR
//                                     curve (OUT_DIR/calibration.txt, OUT_DIR/crr_curve.csv)
//
// The material is PM4Sand from --relative-density or --blow-count ((N1)60 = 46 D_R²; and
// --shear-modulus-coefficient, --contraction-rate), or any material of a case:
// --case CASE.toml --material NAME.
// tools/element_plot.py draws the CSV files (stress path, stress–strain loops, CRR curve).
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
#include "common/input/case_file.hpp"
#include "common/io/atomic_file.hpp"
#include "common/physics/element_test.hpp"
#include "common/physics/pm4sand.hpp"

namespace fs = std::filesystem;
using namespace slide;
using namespace slide::element_test;

namespace {

/// Where the material comes from.
struct MaterialChoice {
  fs::path case_file;
  std::string material;
  double relative_density = std::nan("");
  double blow_count = std::nan("");
  double shear_modulus_coefficient = std::nan("");
  double shear_wave_speed = std::nan("");
  double density = 2000.0;
  double contraction_rate = std::nan("");
  double poisson_ratio = 0.3;
};

Material material_of(const MaterialChoice& choice, bool need_contraction_rate) {
  if (!choice.case_file.empty()) {
    const Case c = load_case(choice.case_file);
    for (const Material& m : c.materials) {
      if (m.name == choice.material) return m;
    }
    throw Error("{}: no material called \"{}\"", choice.case_file.string(), choice.material);
  }
  if (std::isnan(choice.relative_density) == std::isnan(choice.blow_count)) {
    throw Error(
        "give --relative-density or --blow-count (a PM4Sand sand), or --case and --material");
  }
  Material m;
  m.name = "pm4sand";
  m.model = MaterialModel::pm4sand;
  m.density = choice.density;  // only for G₀ from V_s1: an element test has no inertia
  m.poisson_ratio = choice.poisson_ratio;
  m.pm4sand.relative_density = std::isnan(choice.blow_count)
                                   ? choice.relative_density
                                   : pm4sand::relative_density_of(choice.blow_count);
  m.pm4sand.shear_modulus_coefficient = choice.shear_modulus_coefficient;
  if (!std::isnan(choice.shear_wave_speed)) {
    if (!std::isnan(choice.shear_modulus_coefficient)) {
      throw Error("give either --shear-modulus-coefficient or --shear-wave-speed");
    }
    m.pm4sand.shear_modulus_coefficient = pm4sand::shear_modulus_coefficient_from_wave_speed(
        m.density, choice.shear_wave_speed, m.pm4sand.atmospheric_pressure);
  }
  m.pm4sand.contraction_rate = choice.contraction_rate;
  if (std::isnan(m.pm4sand.contraction_rate)) {
    if (need_contraction_rate) throw Error("give --contraction-rate (h_po)");
    m.pm4sand.contraction_rate = 1.0;  // calibrated below
  }
  m.youngs_modulus = pm4sand::elastic_stage_youngs_modulus(m);
  m.validate("slide-element");
  return m;
}

std::string csv(const std::vector<Sample>& history) {
  std::string text =
      "cycles,shear_strain,shear_stress_Pa,vertical_stress_Pa,horizontal_stress_Pa,mean_stress_Pa,"
      "stress_ratio,volumetric_strain,pore_pressure_ratio\n";
  for (const Sample& s : history) {
    text +=
        fmt::format("{:.6f},{:.8g},{:.8g},{:.8g},{:.8g},{:.8g},{:.6g},{:.8g},{:.6f}\n", s.cycles,
                    s.shear_strain, s.shear_stress, s.vertical_stress, s.horizontal_stress,
                    s.mean_stress, s.stress_ratio, s.volumetric_strain, s.pore_pressure_ratio);
  }
  return text;
}

void add_material_options(CLI::App* app, MaterialChoice& m) {
  app->add_option("--relative-density", m.relative_density, "PM4Sand's D_R");
  app->add_option("--blow-count", m.blow_count, "(N1)60, instead of D_R: D_R = sqrt((N1)60/46)");
  app->add_option("--shear-modulus-coefficient", m.shear_modulus_coefficient,
                  "G0 (default 167 sqrt(46 D_R^2 + 2.5))");
  app->add_option("--shear-wave-speed", m.shear_wave_speed,
                  "V_s1, m/s at 1 atm, instead of G0: G0 = rho V_s1^2 / p_A");
  app->add_option("--density", m.density, "rho, kg/m^3, for G0 from V_s1 (default 2000)");
  app->add_option("--contraction-rate", m.contraction_rate, "h_po");
  app->add_option("--poisson-ratio", m.poisson_ratio, "nu (default 0.3)");
  app->add_option("--case", m.case_file, "take the material from this case file instead");
  app->add_option("--material", m.material, "the case's material to test");
}

/// Every option of every subcommand (each subcommand reads its own).
struct Options {
  MaterialChoice choice;
  Consolidation start;
  fs::path out;
  double csr = 0.15;
  double max_cycles = 30.0;
  double strain_limit = 0.03;
  double d_gamma = 1e-5;
  double gamma_max = 0.1;
  double amplitude = 0.001;
  std::string drainage = "drained";
  std::optional<double> target_crr;
  double target_cycles = 15.0;
};

/// A subcommand with its output, the material and the consolidation options.
CLI::App* test_command(CLI::App& app, Options& o, const std::string& name,
                       const std::string& description, const std::string& out) {
  CLI::App* sub = app.add_subcommand(name, description);
  sub->add_option("out", o.out, out)->required();
  add_material_options(sub, o.choice);
  sub->add_option("--vertical-stress", o.start.vertical_stress, "sigma'_v0, Pa (default 101.3e3)")
      ->check(positive_number());
  sub->add_option("--k0", o.start.k0, "K0 (default 0.5)")->check(positive_number());
  sub->add_option("--step", o.d_gamma, "shear strain step (default 1e-5)")
      ->check(positive_number());
  return sub;
}

void run_cyclic(const Options& o) {
  const Material m = material_of(o.choice, true);
  const CyclicResult r = cyclic(m, o.start, o.csr, o.max_cycles, o.strain_limit, o.d_gamma, 10);
  write_text_atomically(o.out, csv(r.history));
  const double limit = 100 * o.strain_limit;
  fmt::print("{}: CSR {:g}: {} (largest r_u {:.3f})\n", o.out.string(), o.csr,
             std::isnan(r.cycles_to_strain)
                 ? fmt::format("{:g} % strain not reached in {:g} cycles", limit, o.max_cycles)
                 : fmt::format("{:g} % strain in {:.2f} cycles", limit, r.cycles_to_strain),
             r.max_pore_pressure_ratio);
}

void run_cyclic_strain(const Options& o) {
  const Material m = material_of(o.choice, true);
  const auto history = cyclic_strain(m, o.start, o.amplitude, o.max_cycles, o.d_gamma);
  write_text_atomically(o.out, csv(history));
  double ru = 0.0;
  for (const Sample& s : history) ru = std::max(ru, s.pore_pressure_ratio);
  fmt::print("{}: gamma = ±{:g} for {:g} cycles: largest r_u {:.3f}, last tau {:.4g} Pa\n",
             o.out.string(), o.amplitude, o.max_cycles, ru, history.back().shear_stress);
}

void run_monotonic(const Options& o) {
  const Material m = material_of(o.choice, true);
  const Drainage drainage = o.drainage == "drained" ? Drainage::drained : Drainage::undrained;
  const auto history = monotonic(m, o.start, drainage, o.gamma_max, o.d_gamma);
  write_text_atomically(o.out, csv(history));
  double peak = 0.0;
  for (const Sample& s : history) peak = std::max(peak, s.stress_ratio);
  fmt::print("{}: peak q/p {:.4f} (phi {:.2f} degrees), at gamma = {:g}: q/p {:.4f}\n",
             o.out.string(), peak, std::asin(std::min(peak / 2.0, 1.0)) * 180.0 / M_PI, o.gamma_max,
             history.back().stress_ratio);
}

/// h_po, then the CRR curve of the calibrated sand at 1 atm (CSR from 0.6 to 2.5 CRR).
void run_calibrate(const Options& o) {
  Material m = material_of(o.choice, false);
  const double dr = m.pm4sand.relative_density;
  const double crr = o.target_crr.value_or(default_target_crr(dr));
  const Calibration cal = calibrate_contraction_rate(m, crr, o.target_cycles);
  m.pm4sand.contraction_rate = cal.contraction_rate;
  const Consolidation atmosphere{m.pm4sand.atmospheric_pressure, 0.5};
  std::string curve = "csr,cycles_to_3pct,max_pore_pressure_ratio\n";
  for (double factor : {0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.25, 1.5, 2.0, 2.5}) {
    const CyclicResult r = cyclic(m, atmosphere, factor * crr, 100.0, 0.03, 1e-5, 1u << 30);
    curve += fmt::format("{:.6g},{:.6g},{:.4f}\n", factor * crr, r.cycles_to_strain,
                         r.max_pore_pressure_ratio);
  }
  fs::create_directories(o.out);
  write_text_atomically(o.out / "crr_curve.csv", curve);
  const std::string summary = fmt::format(
      "relative_density = {}\nblow_count_n160 = {:.3f}\nshear_modulus_coefficient = {:.6g}\n"
      "target_crr = {:.6g}\ntarget_cycles = {:g}\ncontraction_rate = {:.6g}\n"
      "cycles_at_contraction_rate = {:.4f}\nbisection_steps = {}\n",
      dr, pm4sand::blow_count(dr), pm4sand::Constants::of(m).g0, crr, o.target_cycles,
      cal.contraction_rate, cal.cycles, cal.iterations);
  write_text_atomically(o.out / "calibration.txt", summary);
  fmt::print(
      "D_R {:g}: h_po = {:.4g} gives 3 % strain in {:.2f} cycles at CSR = {:.4g} "
      "({} bisection steps); {}\n",
      dr, cal.contraction_rate, cal.cycles, crr, cal.iterations,
      (o.out / "crr_curve.csv").string());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"slide-element: single-point tests of a soil model, and PM4Sand's calibration"};
  app.require_subcommand(1);
  Options o;
  const std::string csv_file = "the CSV file to write";
  CLI::App* cyclic_app =
      test_command(app, o, "cyclic", "undrained cyclic simple shear at a CSR", csv_file);
  cyclic_app->add_option("--csr", o.csr, "tau/sigma'_v0 (default 0.15)")->check(positive_number());
  cyclic_app->add_option("--cycles", o.max_cycles, "at most this many cycles (default 30)")
      ->check(positive_number());
  cyclic_app->add_option("--strain-limit", o.strain_limit, "single-amplitude gamma (default 0.03)")
      ->check(positive_number());
  CLI::App* strain_app = test_command(
      app, o, "cyclic-strain", "undrained cyclic simple shear at a strain amplitude", csv_file);
  strain_app->add_option("--amplitude", o.amplitude, "single-amplitude gamma (default 0.001)")
      ->check(positive_number());
  strain_app->add_option("--cycles", o.max_cycles, "uniform cycles (default 30)")
      ->check(positive_number());
  CLI::App* mono_app = test_command(app, o, "monotonic", "monotonic simple shear", csv_file);
  mono_app->add_option("--drainage", o.drainage, "drained (sigma'_v held) or undrained")
      ->check(CLI::IsMember({"drained", "undrained"}));
  mono_app->add_option("--gamma-max", o.gamma_max, "final shear strain (default 0.1)")
      ->check(positive_number());
  CLI::App* calibrate_app =
      app.add_subcommand("calibrate", "PM4Sand's h_po for a target CRR, and the CRR curve");
  calibrate_app->add_option("out", o.out, "the folder to write into")->required();
  add_material_options(calibrate_app, o.choice);
  calibrate_app->add_option("--crr", o.target_crr,
                            "target CRR (default Idriss-Boulanger 2008 at (N1)60cs = 46 D_R^2)");
  calibrate_app->add_option("--target-cycles", o.target_cycles, "cycles to 3 % strain (default 15)")
      ->check(positive_number());

  if (auto status = parse_command_line(app, argc, argv)) return *status;
  return run_main("slide-element", [&] {
    if (*cyclic_app) {
      run_cyclic(o);
    } else if (*strain_app) {
      run_cyclic_strain(o);
    } else if (*mono_app) {
      run_monotonic(o);
    } else {
      run_calibrate(o);
    }
  });
}
