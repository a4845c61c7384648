// slide-element: single-point tests of a soil model (common/physics/element_test.hpp),
// for checking a material before it goes into a slope, and PM4Sand's calibration.
//
//   slide-element cyclic    OUT.csv   undrained cyclic simple shear at a CSR
//   slide-element monotonic OUT.csv   drained or undrained monotonic simple shear
//   slide-element calibrate OUT_DIR   h_po for a target CRR at 15 cycles, and the CRR
//                                     curve (OUT_DIR/calibration.txt, OUT_DIR/crr_curve.csv)
//
// The material is PM4Sand from --relative-density (and --shear-modulus-coefficient,
// --contraction-rate), or any material of a case: --case CASE.toml --material NAME.
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
  double shear_modulus_coefficient = std::nan("");
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
  if (std::isnan(choice.relative_density)) {
    throw Error("give --relative-density (a PM4Sand sand) or --case and --material");
  }
  Material m;
  m.name = "pm4sand";
  m.model = MaterialModel::pm4sand;
  m.density = 2000.0;  // no inertia in an element test
  m.poisson_ratio = choice.poisson_ratio;
  m.pm4sand.relative_density = choice.relative_density;
  m.pm4sand.shear_modulus_coefficient = choice.shear_modulus_coefficient;
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
  app->add_option("--shear-modulus-coefficient", m.shear_modulus_coefficient,
                  "G0 (default 167 sqrt(46 D_R^2 + 2.5))");
  app->add_option("--contraction-rate", m.contraction_rate, "h_po");
  app->add_option("--poisson-ratio", m.poisson_ratio, "nu (default 0.3)");
  app->add_option("--case", m.case_file, "take the material from this case file instead");
  app->add_option("--material", m.material, "the case's material to test");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"slide-element: single-point tests of a soil model, and PM4Sand's calibration"};
  app.require_subcommand(1);
  MaterialChoice choice;
  Consolidation start;
  fs::path out;
  double csr = 0.15;
  double max_cycles = 30.0;
  double strain_limit = 0.03;
  double d_gamma = 1e-5;
  double gamma_max = 0.1;
  std::string drainage = "drained";
  std::optional<double> target_crr;
  double target_cycles = 15.0;

  auto consolidation = [&](CLI::App* sub) {
    sub->add_option("--vertical-stress", start.vertical_stress, "sigma'_v0, Pa (default 101.3e3)")
        ->check(positive_number());
    sub->add_option("--k0", start.k0, "K0 (default 0.5)")->check(positive_number());
  };
  CLI::App* cyclic_app = app.add_subcommand("cyclic", "undrained cyclic simple shear at a CSR");
  cyclic_app->add_option("out", out, "the CSV file to write")->required();
  add_material_options(cyclic_app, choice);
  consolidation(cyclic_app);
  cyclic_app->add_option("--csr", csr, "tau/sigma'_v0 (default 0.15)")->check(positive_number());
  cyclic_app->add_option("--cycles", max_cycles, "at most this many cycles (default 30)")
      ->check(positive_number());
  cyclic_app->add_option("--strain-limit", strain_limit, "single-amplitude gamma (default 0.03)")
      ->check(positive_number());
  cyclic_app->add_option("--step", d_gamma, "shear strain step (default 1e-5)")
      ->check(positive_number());

  CLI::App* mono_app = app.add_subcommand("monotonic", "monotonic simple shear");
  mono_app->add_option("out", out, "the CSV file to write")->required();
  add_material_options(mono_app, choice);
  consolidation(mono_app);
  mono_app->add_option("--drainage", drainage, "drained (sigma'_v held) or undrained")
      ->check(CLI::IsMember({"drained", "undrained"}));
  mono_app->add_option("--gamma-max", gamma_max, "final shear strain (default 0.1)")
      ->check(positive_number());
  mono_app->add_option("--step", d_gamma, "shear strain step (default 1e-5)")
      ->check(positive_number());

  CLI::App* calibrate_app =
      app.add_subcommand("calibrate", "PM4Sand's h_po for a target CRR, and the CRR curve");
  calibrate_app->add_option("out", out, "the folder to write into")->required();
  add_material_options(calibrate_app, choice);
  calibrate_app->add_option("--crr", target_crr,
                            "target CRR (default Idriss-Boulanger 2008 at (N1)60cs = 46 D_R^2)");
  calibrate_app->add_option("--target-cycles", target_cycles, "cycles to 3 % strain (default 15)")
      ->check(positive_number());

  if (auto status = parse_command_line(app, argc, argv)) return *status;
  return run_main("slide-element", [&] {
    if (*cyclic_app) {
      const Material m = material_of(choice, true);
      const CyclicResult r = cyclic(m, start, csr, max_cycles, strain_limit, d_gamma, 10);
      write_text_atomically(out, csv(r.history));
      fmt::print("{}: CSR {:g}: {} (largest r_u {:.3f})\n", out.string(), csr,
                 std::isnan(r.cycles_to_strain)
                     ? fmt::format("{:g} % strain not reached in {:g} cycles", 100 * strain_limit,
                                   max_cycles)
                     : fmt::format("{:g} % strain in {:.2f} cycles", 100 * strain_limit,
                                   r.cycles_to_strain),
                 r.max_pore_pressure_ratio);
    } else if (*mono_app) {
      const Material m = material_of(choice, true);
      const auto history =
          monotonic(m, start, drainage == "drained" ? Drainage::drained : Drainage::undrained,
                    gamma_max, d_gamma);
      write_text_atomically(out, csv(history));
      double peak = 0.0;
      for (const Sample& s : history) peak = std::max(peak, s.stress_ratio);
      fmt::print("{}: peak q/p {:.4f} (phi {:.2f} degrees), at gamma = {:g}: q/p {:.4f}\n",
                 out.string(), peak, std::asin(std::min(peak / 2.0, 1.0)) * 180.0 / M_PI, gamma_max,
                 history.back().stress_ratio);
    } else {
      Material m = material_of(choice, false);
      const double dr = m.pm4sand.relative_density;
      const double crr = target_crr.value_or(idriss_boulanger_crr(blow_count(dr)));
      const Calibration cal = calibrate_contraction_rate(m, crr, target_cycles);
      m.pm4sand.contraction_rate = cal.contraction_rate;
      const Consolidation atmosphere{m.pm4sand.atmospheric_pressure, 0.5};
      std::string curve = "csr,cycles_to_3pct,max_pore_pressure_ratio\n";
      for (double factor : {0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.25, 1.5, 2.0, 2.5}) {
        const CyclicResult r = cyclic(m, atmosphere, factor * crr, 100.0, 0.03, 1e-5, 1u << 30);
        curve += fmt::format("{:.6g},{:.6g},{:.4f}\n", factor * crr, r.cycles_to_strain,
                             r.max_pore_pressure_ratio);
      }
      fs::create_directories(out);
      write_text_atomically(out / "crr_curve.csv", curve);
      const std::string summary = fmt::format(
          "relative_density = {}\nblow_count_n160 = {:.3f}\nshear_modulus_coefficient = {:.6g}\n"
          "target_crr = {:.6g}\ntarget_cycles = {:g}\ncontraction_rate = {:.6g}\n"
          "cycles_at_contraction_rate = {:.4f}\nbisection_steps = {}\n",
          dr, blow_count(dr), pm4sand::Constants::of(m).g0, crr, target_cycles,
          cal.contraction_rate, cal.cycles, cal.iterations);
      write_text_atomically(out / "calibration.txt", summary);
      fmt::print(
          "D_R {:g}: h_po = {:.4g} gives 3 % strain in {:.2f} cycles at CSR = {:.4g} "
          "({} bisection steps); {}\n",
          dr, cal.contraction_rate, cal.cycles, crr, cal.iterations,
          (out / "crr_curve.csv").string());
    }
  });
}
