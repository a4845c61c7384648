// Benchmark of the FE step loop (not a timed test; fem/README.md quotes the figures).
//
//   OMP_NUM_THREADS=1 build/tools/benchmarks/fem/bench_fem [CASE.toml] [ELEMENT...] [MODEL...]
//
// MODEL (mohr-coulomb, pressure-independent-multi-yield, pm4sand, case) picks the variants
// below (default: all four), e.g. for an instruction count of one of them under callgrind.
// For the case (default cases/column-short/case.toml) and each element type (default:
// quad4-1gp, quad4-2x2, tri3): geostatic stage, switch to the failure models, then the
// failure stage from t = 0 to fem.end_time with the Courant step and no output at all:
// the cost of the physics alone (element forces, nodal update, stress update). Prints
// element-steps per second of that loop, for each element type three times: with every
// material's FE model set to Mohr–Coulomb, to pressure-independent multi-yield, to
// PM4Sand (D_R = 0.55, h_po = 0.45, G₀ p_A the case's G so that its elastic stage is the
// case's; a PM4Sand material of the case keeps its own parameters, and becomes a
// cohesionless φ_cv soil for the other two; all without damping and with the same step, so
// they differ by the constitutive update only), and with the case's own models and damping.
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/base/program.hpp"
#include "common/input/case_file.hpp"
#include "common/input/mesh_generation.hpp"
#include "fem/explicit_dynamics.hpp"
#include "fem/fem_model.hpp"
#include "fem/geostatic.hpp"
#include "fem/model_setup.hpp"
#include "tools/benchmarks/digest.hpp"
#include "tools/benchmarks/instruction_counter.hpp"

namespace {

using namespace slide;
using namespace slide::fem;
using Clock = std::chrono::steady_clock;

void benchmark(Case c, ElementType type, const std::string& label) {
  c.mesh.element_type = type;
  const FemModel model = make_model(build_mesh(c), c.materials, c.fem.kinematics,
                                    c.fem.hourglass_coefficient, c.gravity, c.fem.water);
  FemState state = make_rest_state(model);
  solve_geostatic(model, make_constraints(model.mesh, c.fem.geostatic_boundaries, "geostatic"),
                  state);
  std::vector<ConstitutiveModel> models;
  for (const auto& material : model.materials) models.push_back(ConstitutiveModel::from(material));
  ExplicitSolver solver(model, make_constraints(model.mesh, c.fem.failure_boundaries, "failure"),
                        c.fem.friction_coefficient, damping_of(c.fem.damping), std::move(models));
  solver.return_to_yield_surface(state);
  const double dt =
      c.fem.time_step > 0.0 ? c.fem.time_step : solver.stable_time_step(state, c.fem.courant);
  bench::InstructionCounter counter;  // the main thread's: a count with OMP_NUM_THREADS=1
  const auto start = Clock::now();
  counter.start();
  Index steps = 0;
  while (state.time < c.fem.end_time) {
    solver.step(state, dt);
    ++steps;
  }
  const std::optional<double> instructions = counter.stop();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double element_steps = static_cast<double>(steps * model.element_count());
  fmt::print(
      "{:<10} {:<34} elements={} gauss_points={} steps={} wall_s={:.3f} "
      "element_steps_per_s={:.3g} instructions_per_element_step={} digest={:016x}\n",
      to_string(type), label, model.element_count(), model.gauss_count(), steps, seconds,
      element_steps / seconds,
      instructions ? fmt::format("{:.0f}", *instructions / element_steps)
                   : "n/a (no hardware counter: tools/benchmarks/instructions.sh)",
      bench::digest(state.displacement, state.velocity, state.stress, state.strain,
                    state.material_state, state.surface_stress.values));
}

}  // namespace

int main(int argc, char** argv) {
  slide::prefer_yielding_threads(argv);  // as fem-solve runs
  return slide::run_main("bench_fem", [&] {
    const std::string file = argc > 1 ? argv[1] : SLIDE_SOURCE_DIR "/cases/column-short/case.toml";
    const Case c = load_case(file);
    std::vector<ElementType> types;
    std::vector<std::string> variants;
    for (int i = 2; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "case" || arg == "mohr-coulomb" || arg == "pressure-independent-multi-yield" ||
          arg == "pm4sand") {
        variants.push_back(arg);
      } else {
        types.push_back(parse_element_type(arg, "bench_fem"));
      }
    }
    if (variants.empty()) {
      variants = {"mohr-coulomb", "pressure-independent-multi-yield", "pm4sand", "case"};
    }
    if (types.empty()) types = {ElementType::quad4_1gp, ElementType::quad4_2x2, ElementType::tri3};
    fmt::print("bench_fem: {} ({}), failure stage 0 → {} s, no output\n", c.name,
               to_string(c.fem.kinematics), c.fem.end_time);
    for (const auto type : types) {
      for (const std::string& name : variants) {
        if (name == "case") {
          benchmark(c, type, "case models and damping");
          continue;
        }
        Case variant = c;
        variant.fem.damping = {};
        for (Material& m : variant.materials) {
          const MaterialModel was = m.model;
          m.model = parse_material_model(name, "bench_fem");
          if (m.model == MaterialModel::pm4sand && was != MaterialModel::pm4sand) {
            m.pm4sand.relative_density = 0.55;
            m.pm4sand.contraction_rate = 0.45;
            m.pm4sand.shear_modulus_coefficient =
                m.shear_modulus() / m.pm4sand.atmospheric_pressure;
          } else if (has_strength(m.model) && was == MaterialModel::pm4sand) {
            // A sand's strength at critical state, cohesionless.
            m.friction_angle = m.pm4sand.critical_friction_angle;
            m.cohesion = 0.0;
            m.tension_cutoff = 0.0;
          }
        }
        benchmark(variant, type, name + " (undamped)");
      }
    }
  });
}
