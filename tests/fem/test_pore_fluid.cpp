// Saturated soil, explicit u–p (fem/pore_fluid.hpp, docs/method.md §10), against closed
// forms: the hydrostatic rest state, the sealed oedometer's undrained pore pressure and
// Terzaghi's consolidation of a column drained at the top.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <tuple>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "fem/element_kernels.hpp"
#include "fem/explicit_dynamics.hpp"
#include "fem/fem_model.hpp"
#include "fem/geostatic.hpp"
#include "fem/model_setup.hpp"
#include "fem/pore_fluid.hpp"
#include "fem/seismic_boundary.hpp"
#include "tests/support/meshes.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide::fem {
namespace {

using testing::rectangle_mesh;

const std::array<ElementType, 3> all_types{ElementType::quad4_1gp, ElementType::quad4_2x2,
                                           ElementType::tri3};

/// A loose saturated sand: ρ_sat 2000 kg/m³, E 10 MPa, ν 0.3 (M = 13.46 MPa), n 0.4.
Material sand(double conductivity) {
  Material m = synthetic::soil(MaterialModel::linear_elastic, 2000.0);
  m.youngs_modulus = 10e6;
  m.poisson_ratio = 0.3;
  m.porosity = 0.4;
  m.conductivity_x = m.conductivity_y = conductivity;
  return m;
}

WaterSpec water_at(double level, double bulk_modulus = 2.2e9) {
  WaterSpec w;
  w.level = level;
  w.bulk_modulus = bulk_modulus;
  return w;
}

std::vector<ConstitutiveModel> models_of(const FemModel& model) {
  std::vector<ConstitutiveModel> models;
  for (const auto& m : model.materials) models.push_back(ConstitutiveModel::from(m));
  return models;
}

const BoundaryTable box{{"left", BoundaryCondition::roller},
                        {"right", BoundaryCondition::roller},
                        {"base", BoundaryCondition::roller}};

// Hydrostatic p and effective K0 stresses: the geostatic state of a saturated column is
// at rest in the explicit stage, p stays the hydrostatic field and σ′v = (ρ_sat − ρ_w) g z
// below the table. With the table at the top and through the middle of an element row,
// on a distorted mesh, for every element type.
TEST(PoreFluid, HydrostaticRestIsExact) {
  constexpr double height = 10.0, g = 9.81;
  for (const auto type : all_types) {
    for (const double level : {height, 6.5}) {
      SCOPED_TRACE(fmt::format("{}, water level {} m", to_string(type), level));
      Mesh mesh = rectangle_mesh(type, 4, 10, 4.0, height);
      testing::distort_interior(mesh, 1.0, 0.2);
      const Material material = sand(1e-4);
      const FemModel model = make_model(std::move(mesh), {material}, Kinematics::small_strain, 1.0,
                                        Vec2(0.0, -g), water_at(level));
      FemState state = make_rest_state(model);
      solve_geostatic(model, make_constraints(model.mesh, box, "test"), state);
      const std::vector<double> p0 = state.pore_pressure;
      ExplicitSolver solver(model, make_constraints(model.mesh, box, "test"), 0.0, {},
                            models_of(model));
      const double dt = solver.stable_time_step(state, 0.5);
      for (int i = 0; i < 200; ++i) solver.step(state, dt);
      double speed = 0.0, p_change = 0.0;
      for (const Vec2& v : state.velocity) speed = std::max(speed, v.norm());
      for (std::size_t n = 0; n < p0.size(); ++n) {
        p_change = std::max(p_change, std::abs(state.pore_pressure[n] - p0[n]));
        const Vec2& x = model.mesh.nodes[n];
        if (model.fluid.node_storage[n] > 0.0) {
          EXPECT_NEAR(p0[n], std::max(1000.0 * g * (level - x.y()), -100e3), 1e-9) << n;
        }
      }
      EXPECT_LT(speed, 1e-9);  // gravity alone: g·200·dt ≈ 0.1 m/s
      EXPECT_LT(p_change, 1e-9 * 1000.0 * g * height);
    }
  }
}

// The effective vertical stress of the geostatic stage at the one-point quads' centres of
// an undistorted column: (ρ_sat − ρ_w) g z below the table, ρ_dry g z above it.
TEST(PoreFluid, GeostaticStageCarriesTheEffectiveStress) {
  constexpr double height = 10.0, g = 9.81, level = 6.0;
  const Material material = sand(1e-4);
  const FemModel model =
      make_model(rectangle_mesh(ElementType::quad4_1gp, 1, 10, 1.0, height), {material},
                 Kinematics::small_strain, 1.0, Vec2(0.0, -g), water_at(level));
  FemState state = make_rest_state(model);
  solve_geostatic(model, make_constraints(model.mesh, box, "test"), state);
  const double dry = material.density - material.porosity * 1000.0;
  for (Index e = 0; e < model.element_count(); ++e) {
    const double y = static_cast<double>(e) + 0.5;  // centre of element e
    const double above = std::min(height - y, height - level);
    const double below = std::max(level - y, 0.0);
    const double expected = -(dry * g * above + (material.density - 1000.0) * g * below);
    EXPECT_NEAR(state.stress[static_cast<std::size_t>(e)][1], expected, 1e-8 * std::abs(expected))
        << "element " << e;
    EXPECT_NEAR(state.stress[static_cast<std::size_t>(e)][0],
                material.k0() * state.stress[static_cast<std::size_t>(e)][1],
                1e-8 * std::abs(expected));
  }
}

// Upward seepage at the critical gradient (docs/method.md §10, check 4): a 10 m saturated
// column in geostatic equilibrium, drained at the top (the table there), is given at its
// base a drained face at the pressure that drives water upwards at the critical gradient
// i_c = (ρ_sat − ρ_w)/ρ_w: p_base = ρ_w g H (1 + i_c) = ρ_sat g H. The flow settles to the
// linear p = ρ_sat g (H − y), which is the total vertical stress, so σ′v → 0 everywhere (the
// soil is at the point of boiling). Consolidation time: c_v t/H² = 1 with both ends
// drained leaves e^(−π²) of the transient.
TEST(PoreFluid, UpwardSeepageAtTheCriticalGradientTakesTheEffectiveStressAway) {
  constexpr double height = 10.0, g = 9.81, k = 1e-3, bulk_modulus = 0.2e9;
  const Material material = sand(k);
  FemModel model =
      make_model(rectangle_mesh(ElementType::quad4_1gp, 1, 10, 1.0, height), {material},
                 Kinematics::small_strain, 1.0, Vec2(0.0, -g), water_at(height, bulk_modulus));
  FemState state = make_rest_state(model);
  solve_geostatic(model, make_constraints(model.mesh, box, "test"), state);
  const double initial = -state.stress[0][1];  // σ′v0 of the lowest element
  // The base's drained face: from the lowest element's centre to the base's midpoint.
  const double base_pressure = material.density * g * height;
  model.fluid.faces.push_back(
      FluidFace{0, -1, 2.0 * k / (1000.0 * 9.81), Vec2(0.0, -0.5), base_pressure});
  const double cv =
      (k / (1000.0 * 9.81)) / (1.0 / material.p_wave_modulus() + material.porosity / bulk_modulus);
  ExplicitSolver solver(model, make_constraints(model.mesh, box, "test"), 0.0,
                        Damping{NodalDamping{0.0, 0.8}, 0.0}, models_of(model));
  const double dt = solver.stable_time_step(state, 0.5);
  while (state.time < height * height / cv) solver.step(state, dt);
  double largest = 0.0;
  for (Index e = 0; e < model.element_count(); ++e) {
    const auto ei = static_cast<std::size_t>(e);
    largest = std::max(largest, std::abs(state.stress[ei][1]));
    const double y = static_cast<double>(e) + 0.5;
    EXPECT_NEAR(state.element_pore_pressure[ei], material.density * g * (height - y),
                1e-3 * base_pressure)
        << "element " << e;
  }
  std::printf("seepage at i_c: largest |σ′v| %.3g Pa of σ′v0 = %.4g Pa at the base (%.2e)\n",
              largest, initial, largest / initial);
  EXPECT_LT(largest, 1e-3 * initial);
}

/// How far `steps` undamped steps of the explicit stage (box supports, C = 0.5) move a
/// state that should be at rest: its largest speed and element pressure change.
struct Drift {
  double speed = 0.0;     ///< m/s
  double pressure = 0.0;  ///< Pa
};
Drift run_undamped(const FemModel& model, FemState& state, int steps) {
  ExplicitSolver solver(model, make_constraints(model.mesh, box, "test"), 0.0, {},
                        models_of(model));
  const double dt = solver.stable_time_step(state, 0.5);
  const std::vector<double> p0 = state.element_pore_pressure;
  for (int i = 0; i < steps; ++i) solver.step(state, dt);
  Drift drift;
  for (const Vec2& v : state.velocity) drift.speed = std::max(drift.speed, v.norm());
  for (std::size_t e = 0; e < p0.size(); ++e) {
    drift.pressure = std::max(drift.pressure, std::abs(state.element_pore_pressure[e] - p0[e]));
  }
  return drift;
}

// A reservoir (docs/method.md §10): a saturated block with a sloping top, wholly under a
// reservoir 2 m above its highest point, is the buoyant block: its geostatic effective
// stresses are those of the same block without water and with the buoyant density
// ρ_sat − ρ_w, to first order in h, and the explicit stage keeps it at rest. Without the
// water's load on the wetted surface the pore pressure's push would lift the skeleton.
TEST(PoreFluid, SubmergedBlockUnderAReservoirIsBuoyant) {
  constexpr double g = 9.81;
  const Material material = sand(1e-4);
  Material buoyant = material;
  buoyant.density = material.density - 1000.0;
  buoyant.porosity = 0.0;
  buoyant.conductivity_x = buoyant.conductivity_y = 0.0;
  std::vector<double> differences;
  for (const int cells : {8, 16}) {
    SCOPED_TRACE(fmt::format("{} × {} cells", cells, cells));
    Mesh mesh = rectangle_mesh(ElementType::quad4_1gp, cells, cells, 8.0, 8.0);
    for (Vec2& x : mesh.nodes) x.y() *= 1.0 - 0.04 * x.x();  // the top slopes from 8 to 5.44 m
    WaterSpec water = water_at(10.0);
    water.reservoir = 10.0;
    const FemModel model =
        make_model(Mesh(mesh), {material}, Kinematics::small_strain, 1.0, Vec2(0.0, -g), water);
    FemState state = make_rest_state(model);
    solve_geostatic(model, make_constraints(model.mesh, box, "test"), state);
    const FemModel dry = make_model(std::move(mesh), {buoyant}, Kinematics::small_strain, 1.0,
                                    Vec2(0.0, -g), std::nullopt);
    FemState dry_state = make_rest_state(dry);
    solve_geostatic(dry, make_constraints(dry.mesh, box, "test"), dry_state);
    double largest = 0.0, difference = 0.0;
    for (std::size_t gp = 0; gp < state.stress.size(); ++gp) {
      largest = std::max(largest, dry_state.stress[gp].cwiseAbs().maxCoeff());
      difference =
          std::max(difference, (state.stress[gp] - dry_state.stress[gp]).cwiseAbs().maxCoeff());
    }
    std::printf("submerged block, %d cells: largest |σ′ − σ′ buoyant| %.4g Pa of %.4g Pa\n", cells,
                difference, largest);
    differences.push_back(difference / largest);
    const Drift drift = run_undamped(model, state, 200);
    EXPECT_LT(drift.speed, 1e-9);
    EXPECT_LT(drift.pressure, 1e-9 * 1000.0 * g * 10.0);
  }
  // The wetted surface's linear pressure against the elements' constant p: a first-order
  // difference, 0.44 % at 1 m and 0.21 % at 0.5 m (59 % without the water's load).
  EXPECT_LT(differences[0], 0.01);
  EXPECT_LT(differences[1], 0.6 * differences[0]);
}

// A sealed saturated element in cyclic simple shear (docs/method.md §10, check 6): one
// one-point quad, k = 0, on a fixed base, under a vertical load of 100 kPa carried by the
// skeleton and a cyclic shear stress τ = 30 kPa sin(2π t) on its top (two cycles, brought
// through quasi-statically by local damping). As K_f grows the element's stress path
// becomes the soil's constant-volume one: Mohr–Coulomb (φ = 30°, c = 0, ψ = 10°) driven by
// the element's own ε_xx and γ with ε_yy = −ε_xx — a dilatant sand whose pore water takes
// the dilation away, so that σ′ climbs the failure line. The difference falls as 1/K_f.
TEST(PoreFluid, SealedElementInCyclicSimpleShearIsConstantVolumeAsTheFluidStiffens) {
  constexpr double q = 100e3, tau = 30e3, duration = 2.0;
  Material soil = synthetic::soil(MaterialModel::mohr_coulomb, 2000.0);
  soil.youngs_modulus = 20e6;
  soil.poisson_ratio = 0.3;
  soil.friction_angle = 30.0;
  soil.cohesion = 0.0;
  soil.dilation_angle = 10.0;
  soil.porosity = 0.4;
  const Vec4 initial(-soil.k0() * q, -q, -soil.k0() * q, 0.0);
  std::vector<double> differences;
  for (const double bulk_modulus : {2.2e8, 2.2e9, 2.2e10}) {
    SCOPED_TRACE(fmt::format("K_f = {} Pa", bulk_modulus));
    FemModel model =
        make_model(rectangle_mesh(ElementType::quad4_1gp, 1, 1, 1.0, 1.0), {soil},
                   Kinematics::small_strain, 1.0, Vec2::Zero(), water_at(10.0, bulk_modulus));
    const std::vector<Index> top = model.mesh.find_node_set("top")->nodes;
    for (const Index n : top)
      model.lumped.external_force[static_cast<std::size_t>(n)].y() = -0.5 * q;
    FemState state = make_rest_state(model);
    state.stress[0] = initial;
    const std::vector<ConstitutiveModel> models{ConstitutiveModel::from(soil)};
    ExplicitSolver solver(
        model, make_constraints(model.mesh, {{"base", BoundaryCondition::fixed}}, "test"), 0.0,
        Damping{NodalDamping{0.0, 0.8}, 0.0}, models);
    const double dt = solver.stable_time_step(state, 0.5);
    Vec4 reference = initial, strain = Vec4::Zero();
    MaterialState point;
    double difference = 0.0, volume = 0.0;
    while (state.time < duration - 0.5 * dt) {
      // The solver reads the model's external forces each step: the shear load's history.
      const double shear = tau * std::sin(2.0 * std::numbers::pi * state.time);
      for (const Index n : top)
        model.lumped.external_force[static_cast<std::size_t>(n)].x() = 0.5 * shear;
      solver.step(state, dt);
      const Vec4 increment = state.strain[0] - strain;
      strain = state.strain[0];
      models[0].update(reference, point, Vec4(increment[0], -increment[0], 0.0, increment[3]));
      difference = std::max(difference, (state.stress[0] - reference).cwiseAbs().maxCoeff());
      volume = std::max(volume, std::abs(strain[0] + strain[1]));
    }
    std::printf(
        "simple shear, K_f = %.1e Pa: largest |σ′ − σ′ constant volume| %.4g Pa (%.3g of q), "
        "|ε_v| ≤ %.2e, final σ′yy %.5g Pa (constant volume %.5g), γ %.5f\n",
        bulk_modulus, difference, difference / q, volume, state.stress[0][1], reference[1],
        strain[3]);
    differences.push_back(difference / q);
  }
  EXPECT_LT(differences[2], 0.01);
  EXPECT_LT(differences[1], 0.2 * differences[0]);
  EXPECT_LT(differences[2], 0.2 * differences[1]);
}

// A reservoir whose surface crosses the sloping top between nodes (at y = 7 m, the top
// going from 8 to 5.44 m), with the table at the same level: the state is hydrostatic and
// at rest. The side the surface crosses is drained at the pressure of its midpoint and
// loaded only where it is wet; a pressure averaged from the nodes would push water in
// from the first step.
TEST(PoreFluid, AReservoirSurfaceCrossingASideLeavesTheSlopeAtRest) {
  constexpr double g = 9.81;
  Mesh mesh = rectangle_mesh(ElementType::quad4_1gp, 8, 8, 8.0, 8.0);
  for (Vec2& x : mesh.nodes) x.y() *= 1.0 - 0.04 * x.x();
  WaterSpec water = water_at(7.0);
  water.reservoir = 7.0;
  const FemModel model = make_model(std::move(mesh), {sand(1e-4)}, Kinematics::small_strain, 1.0,
                                    Vec2(0.0, -g), water);
  FemState state = make_rest_state(model);
  solve_geostatic(model, make_constraints(model.mesh, box, "test"), state);
  const Drift drift = run_undamped(model, state, 500);
  EXPECT_LT(drift.speed, 1e-9);
  EXPECT_LT(drift.pressure, 1e-9 * 1000.0 * g * 8.0);
}

// The elements' p from a nodal one (a checkpoint written before elements carried p, an
// OpenSees u–p recorder): the mean of the nodes in saturated elements, 0 in dry ones.
TEST(PoreFluid, ElementPressureFromNodesIsZeroInDryElements) {
  const FemModel model =
      make_model(rectangle_mesh(ElementType::quad4_1gp, 1, 10, 1.0, 10.0), {sand(1e-4)},
                 Kinematics::small_strain, 1.0, Vec2(0.0, -9.81), water_at(6.0));
  std::vector<double> nodal(static_cast<std::size_t>(model.node_count()));
  for (std::size_t n = 0; n < nodal.size(); ++n) nodal[n] = model.mesh.nodes[n].y();
  const std::vector<double> p = element_pressure_from_nodes(model, nodal);
  for (Index e = 0; e < model.element_count(); ++e) {
    const auto ei = static_cast<std::size_t>(e);
    EXPECT_EQ(p[ei], model.fluid.saturated[ei] ? static_cast<double>(e) + 0.5 : 0.0) << e;
  }
  EXPECT_EQ(std::ranges::count(model.fluid.saturated, std::uint8_t{1}), 6);
}

/// A column 1 m wide of `rows` elements between rollers, no gravity, loaded on its top
/// by q (nodal forces), the water table at `level`, under local damping α for the
/// quasi-static runs. Returns the model with the load in its external forces.
FemModel loaded_column(int rows, double height, double q, double level, double conductivity,
                       double bulk_modulus) {
  FemModel model =
      make_model(rectangle_mesh(ElementType::quad4_1gp, 1, rows, 1.0, height), {sand(conductivity)},
                 Kinematics::small_strain, 1.0, Vec2::Zero(), water_at(level, bulk_modulus));
  const NodeSet* top = model.mesh.find_node_set("top");
  for (const Index n : top->nodes)
    model.lumped.external_force[static_cast<std::size_t>(n)].y() -= 0.5 * q;
  return model;
}

// Sealed (k = 0) oedometric column under a load q: p = q (K_f/n)/(M + K_f/n) everywhere,
// σ′v = −q M/(M + K_f/n), for the real K_f and a lowered one.
TEST(PoreFluid, SealedOedometerTakesTheUndrainedShare) {
  constexpr double q = 100e3;
  for (const double bulk_modulus : {2.2e9, 0.05e9}) {
    SCOPED_TRACE(fmt::format("K_f = {} Pa", bulk_modulus));
    const FemModel model = loaded_column(4, 4.0, q, 100.0, 0.0, bulk_modulus);
    FemState state = make_rest_state(model);
    ExplicitSolver solver(model, make_constraints(model.mesh, box, "test"), 0.0,
                          Damping{NodalDamping{0.0, 0.8}, 0.0}, models_of(model));
    const double dt = solver.stable_time_step(state, 0.5);
    for (int i = 0; i < 4000; ++i) solver.step(state, dt);
    const double fluid = bulk_modulus / 0.4;
    const double m = sand(0.0).p_wave_modulus();
    for (const double p : state.pore_pressure) EXPECT_NEAR(p, q * fluid / (m + fluid), 1e-6 * q);
    for (const Vec4& s : state.stress) EXPECT_NEAR(s[1], -q * m / (m + fluid), 1e-6 * q);
  }
}

/// Terzaghi's excess pore pressure u/u₀ at depth z of a layer of height H drained at the
/// top, at time factor T: Σ_m (2/M_m) sin(M_m z/H) exp(−M_m² T), M_m = (2m + 1)π/2.
double terzaghi(double z_over_h, double time_factor) {
  double u = 0.0;
  for (int m = 0; m < 200; ++m) {
    const double big_m = (2 * m + 1) * std::numbers::pi / 2.0;
    u += 2.0 / big_m * std::sin(big_m * z_over_h) * std::exp(-big_m * big_m * time_factor);
  }
  return u;
}

// Terzaghi: a 10 m column of 40 elements drained at the top (the water table there),
// impermeable at the base, loaded at t = 0. At T = 0.05 … 1 the pore pressure at the base
// and at mid-height is the series' within 1 % of u₀, with c_v = (k/γ_w)/(1/M + n/K_f):
// quasi-static (from rest, loaded suddenly, local damping 0.8 removing the load's waves)
// and dynamic (undamped, from Terzaghi's own initial state, the undrained response to the
// load: p = u₀, σ′ of the skeleton strain −q/(M + K_f/n); loaded suddenly from rest the
// undamped waves ring at 30 % of u₀ at T = 0.05, and the flow damps them only slowly).
TEST(PoreFluid, TerzaghiConsolidation) {
  constexpr double height = 10.0, q = 100e3, k = 1e-3, bulk_modulus = 0.2e9;
  const Material material = sand(k);
  const double m = material.p_wave_modulus();
  const double cv = (k / (1000.0 * 9.81)) / (1.0 / m + 0.4 / bulk_modulus);
  const double u0 = q * (bulk_modulus / 0.4) / (m + bulk_modulus / 0.4);
  for (const bool dynamic : {false, true}) {
    SCOPED_TRACE(dynamic ? "dynamic" : "quasi-static");
    const FemModel model = loaded_column(40, height, q, height, k, bulk_modulus);
    FemState state = make_rest_state(model);

    if (dynamic) {
      const double strain = -(q - u0) / m;  // ε_yy of the undrained response
      const double lambda = material.lame_lambda();
      for (Vec4& s : state.stress) s = Vec4(lambda * strain, m * strain, lambda * strain, 0.0);
      std::ranges::fill(state.element_pore_pressure, u0);
      update_nodal_pore_pressure(model, state);
    }
    const Damping damping{NodalDamping{0.0, dynamic ? 0.0 : 0.8}, 0.0};
    ExplicitSolver solver(model, make_constraints(model.mesh, box, "test"), 0.0, damping,
                          models_of(model));
    const double dt = solver.stable_time_step(state, 0.5);
    const auto base = static_cast<std::size_t>(model.mesh.find_node_set("base")->nodes[0]);
    const auto middle = base + 2 * 20;  // node (0, 20): y = 5 m
    ASSERT_NEAR(model.mesh.nodes[middle].y(), 5.0, 1e-12);
    double worst = 0.0;
    for (const double time_factor : {0.05, 0.1, 0.2, 0.5, 1.0}) {
      const double until = time_factor * height * height / cv;
      while (state.time < until - 0.5 * dt) solver.step(state, std::min(dt, until - state.time));
      for (const auto& [node, z] : {std::pair{base, 1.0}, std::pair{middle, 0.5}}) {
        const double error = std::abs(state.pore_pressure[node] / u0 - terzaghi(z, time_factor));
        worst = std::max(worst, error);
        EXPECT_LT(error, 0.01) << "T = " << time_factor << ", z/H = " << z << ": u/u0 "
                               << state.pore_pressure[node] / u0 << ", series "
                               << terzaghi(z, time_factor);
      }
    }
    std::printf(
        "Terzaghi (%s): largest |u/u0 - series| at the base and mid-height %.2e, %lld steps\n",
        dynamic ? "dynamic" : "quasi-static", worst, static_cast<long long>(state.step));
  }
}

// The water the drained faces let out (drained_outflow, the recorders' `outflow`) is the
// water the column lost: over the quasi-static Terzaghi column's consolidation to T = 1,
// ∫ outflow dt = −ΔV − Σ S_e Δp_e (the skeleton's volume change and the water's
// compression), with ΔV the top's settlement times the column's width.
TEST(PoreFluid, DrainedOutflowIsTheWaterTheColumnLoses) {
  constexpr double height = 10.0, q = 100e3, k = 1e-3, bulk_modulus = 0.2e9;
  const FemModel model = loaded_column(40, height, q, height, k, bulk_modulus);
  FemState state = make_rest_state(model);
  ExplicitSolver solver(model, make_constraints(model.mesh, box, "test"), 0.0,
                        Damping{NodalDamping{0.0, 0.8}, 0.0}, models_of(model));
  const double dt = solver.stable_time_step(state, 0.5);
  const Material material = sand(k);
  const double cv =
      (k / (1000.0 * 9.81)) / (1.0 / material.p_wave_modulus() + material.porosity / bulk_modulus);
  const auto outflow = [&] {
    double sum = 0.0;
    for (const FluidFace& face : model.fluid.faces) {
      if (face.to < 0) sum += drained_outflow(model, state, face);
    }
    return sum;
  };
  double out = 0.0, rate = outflow();
  while (state.time < height * height / cv) {
    solver.step(state, dt);
    const double next = outflow();
    out += 0.5 * (rate + next) * dt;
    rate = next;
  }
  const auto top = static_cast<std::size_t>(model.mesh.find_node_set("top")->nodes[0]);
  const double volume_change = state.displacement[top].y() * 1.0;  // negative: settled
  double compression = 0.0;
  for (std::size_t e = 0; e < model.fluid.storage.size(); ++e) {
    compression += model.fluid.storage[e] * state.element_pore_pressure[e];
  }
  std::printf("outflow %.6e m³/m, lost %.6e m³/m (settlement %.4e m)\n", out,
              -volume_change - compression, -volume_change);
  EXPECT_NEAR(out, -volume_change - compression, 1e-3 * std::abs(volume_change));
}

// Stiffness-proportional damping β_K acts on the skeleton (β_K D ε̇), not on the water's
// K_f/n, so the step it allows comes from the skeleton's highest frequency
// (damped_time_step with the skeleton's Courant step). A sealed saturated block with
// β_K = 0.01 s (ξ_max would be 40 against the undrained P wave, the step 80 times
// shorter), started from an alternating velocity field (the highest modes), stays bounded
// and loses its energy at the step that rule gives with C = 0.9 (0.86 of the undamped
// Courant step), and runs away at 1.5 times it (past the undamped limit: the test can fail).
TEST(PoreFluid, StiffnessDampingOfTheSkeletonSetsTheDampedStep) {
  FemModel model = make_model(rectangle_mesh(ElementType::quad4_1gp, 4, 8, 4.0, 8.0), {sand(0.0)},
                              Kinematics::small_strain, 1.0, Vec2::Zero(), water_at(10.0));
  const double beta = 0.01;
  for (const double factor : {1.0, 1.5}) {
    SCOPED_TRACE(fmt::format("{} × the step", factor));
    FemState state = make_rest_state(model);
    for (std::size_t n = 0; n < state.velocity.size(); ++n) {
      const double sign = (n % 2 == 0) == ((n / 5) % 2 == 0) ? 1.0 : -1.0;  // 5 nodes a row
      state.velocity[n] = sign * Vec2(1e-3, 1e-3);
    }
    ExplicitSolver solver(model, make_constraints(model.mesh, box, "test"), 0.0,
                          Damping{NodalDamping{0.0, 0.0}, beta}, models_of(model));
    const double undamped = solver.critical_time_step(state);
    const double dt = factor * solver.stable_time_step(state, 0.9);
    double speed = 0.0;
    for (int i = 0; i < 5000; ++i) solver.step(state, dt);
    for (const Vec2& v : state.velocity) {
      if (!(v.norm() <= speed)) speed = v.norm();  // a NaN stays
    }
    std::printf(
        "β_K = %g s: dt = %.3g s (%.3g of the undamped Courant step), largest speed "
        "after 5000 steps %.3g m/s\n",
        beta, dt, dt / undamped, speed);
    if (factor == 1.0) {
      EXPECT_LT(speed, 1e-3);
      // The skeleton's rule: far longer than the whole mixture's would give.
      EXPECT_GT(dt, 5.0 * damped_time_step(undamped, 0.9, beta));
    } else {
      EXPECT_FALSE(speed < 1.0);  // ran away (or NaN)
    }
  }
}

/// Every node held by a roller whose normal is `normal` (the velocity along it fixed).
NodalConstraints everywhere(const FemModel& model, const Vec2& normal) {
  NodalConstraints c;
  for (Index n = 0; n <= model.node_count(); ++n) c.offsets.push_back(n);
  c.constraints.assign(static_cast<std::size_t>(model.node_count()),
                       NodalConstraint{BoundaryCondition::roller, normal});
  return c;
}

/// The time of the largest |v · direction| at `node` over [from, to], refined by the
/// parabola through the largest sample and its neighbours.
struct Peak {
  double time = 0.0, value = -1.0;
};

// Undrained (k = 0) saturated column, 100 m of 400 quads: a Gaussian velocity pulse
// (σ = 2 m) started at y = 70 m splits into two; the downward half passes y = 60 and
// y = 30 m 30 m / V apart. Shear (horizontal velocity, every node's vertical velocity
// held): V_s = sqrt(G/ρ_sat), the water carrying no shear. Compression (vertical
// velocity, horizontal held): the undrained V_p,u = sqrt((M + K_f/n)/ρ_sat).
TEST(PoreFluid, UndrainedWavesTravelAtTheirSpeeds) {
  constexpr double height = 100.0, start = 70.0, width = 2.0;
  const Material material = sand(0.0);
  const double shear = std::sqrt(material.shear_modulus() / material.density);
  const double compression =
      std::sqrt((material.p_wave_modulus() + 2.2e9 / 0.4) / material.density);
  for (const auto& [name, direction, speed] :
       {std::tuple{"S", Vec2(1.0, 0.0), shear}, std::tuple{"P", Vec2(0.0, 1.0), compression}}) {
    SCOPED_TRACE(name);
    const FemModel model =
        make_model(rectangle_mesh(ElementType::quad4_1gp, 1, 400, 0.25, height), {material},
                   Kinematics::small_strain, 1.0, Vec2::Zero(), water_at(height + 1.0));
    FemState state = make_rest_state(model);
    for (std::size_t n = 0; n < state.velocity.size(); ++n) {
      const double d = (model.mesh.nodes[n].y() - start) / width;
      state.velocity[n] = 0.01 * std::exp(-0.5 * d * d) * direction;
    }
    ExplicitSolver solver(model, everywhere(model, Vec2(direction.y(), direction.x())), 0.0, {},
                          models_of(model));
    const double dt = solver.stable_time_step(state, 0.5);
    // Nodes (0, j) at y = 60 and 30 m: j = 240 and 120, index 2 j.
    const std::array<std::size_t, 2> nodes{480, 240};
    std::array<std::array<double, 3>, 2> last{};  // the last three samples
    std::array<Peak, 2> peaks{};
    const double until = (start - 30.0 + 4.0 * width) / speed;
    while (state.time < until) {
      solver.step(state, dt);
      for (std::size_t i = 0; i < 2; ++i) {
        last[i] = {last[i][1], last[i][2], state.velocity[nodes[i]].dot(direction)};
        const auto& [a, b, c] = last[i];
        if (b > a && b >= c && b > peaks[i].value) {
          // Vertex of the parabola through (−dt, a), (0, b), (dt, c).
          const double shift = 0.5 * dt * (a - c) / (a - 2.0 * b + c);
          peaks[i] = {state.time - dt + shift, b};
        }
      }
    }
    const double measured = 30.0 / (peaks[1].time - peaks[0].time);
    std::printf("undrained %s wave: %.2f m/s, closed form %.2f m/s (%+.3f %%)\n", name, measured,
                speed, 100.0 * (measured / speed - 1.0));
    EXPECT_NEAR(measured / speed, 1.0, 0.01);
  }
}

/// The chequerboard of a pressure field on an (nx + 1) × (ny + 1) grid of points (the
/// nodes, or the centres, of a grid of equal rectangles): for each cell, the part of
/// |p_k − cell mean| that alternates from corner to corner, |p₁ − p₂ + p₃ − p₄|/4 (0 for any
/// bilinear field, the whole amplitude of a chequerboard; a smooth field gives
/// h² |∂²p/∂x∂y|/4), over `scale`: the 99th percentile over the cells whose mean p is at
/// least a tenth of the largest.
double chequerboard(const std::vector<double>& p, int nx, int ny, double scale) {
  const auto at = [&](int i, int j) { return p[static_cast<std::size_t>(j * (nx + 1) + i)]; };
  const double largest = *std::max_element(p.begin(), p.end());
  std::vector<double> amplitude;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double mean = 0.25 * (at(i, j) + at(i + 1, j) + at(i + 1, j + 1) + at(i, j + 1));
      if (mean < 0.1 * largest) continue;
      amplitude.push_back(std::abs(at(i, j) - at(i + 1, j) + at(i + 1, j + 1) - at(i, j + 1)) /
                          (4.0 * scale));
    }
  }
  std::sort(amplitude.begin(), amplitude.end());
  return amplitude[static_cast<std::size_t>(0.99 * static_cast<double>(amplitude.size() - 1))];
}

// The undrained strip load (docs/method.md §10, check 5): a sealed saturated layer 20 m wide
// and 10 m deep (k = 0, K_f = 2.2 GPa: nearly incompressible) under a strip load of 100 kPa
// 4 m wide at the top centre, brought to rest by local damping, coarse (1 m) and fine
// (0.5 m) one-point quads. No pressure chequerboard in the elements' p (the unknown) nor
// in the nodal p of the output: the 99th percentile of the alternating part of
// |p − cell mean| (chequerboard above) is below 5 % of q.
//
// The measure and the candidates (fem/README.md, "Pore water"): the 3 × 3 patch mean of
// the first draft of this test also counts the curvature of a smooth field that a 1 m mesh
// resolves with a few points beside the strip's edges, and failed every candidate at
// h = 1 m, smooth ones too; the alternating part is what a chequerboard is. With it, nodal
// p (candidate (a), nodal averaging) gives 10.4 % and 2.8 %; element p (candidate (c),
// built) passes.
TEST(PoreFluid, UndrainedStripLoadHasNoChequerboard) {
  constexpr double width = 20.0, depth = 10.0, q = 100e3, half_strip = 2.0;
  for (const double h : {1.0, 0.5}) {
    SCOPED_TRACE(fmt::format("h = {} m", h));
    const int nx = static_cast<int>(width / h), ny = static_cast<int>(depth / h);
    FemModel model =
        make_model(rectangle_mesh(ElementType::quad4_1gp, nx, ny, width, depth), {sand(0.0)},
                   Kinematics::small_strain, 1.0, Vec2::Zero(), water_at(depth + 1.0));
    for (const Index n : model.mesh.find_node_set("top")->nodes) {
      const double x = model.mesh.nodes[static_cast<std::size_t>(n)].x() - 0.5 * width;
      // The nodal share of a uniform load on [−2, 2] m: h inside, h/2 at its edges.
      const double share = std::abs(x) < half_strip - 1e-9             ? h
                           : std::abs(std::abs(x) - half_strip) < 1e-9 ? 0.5 * h
                                                                       : 0.0;
      model.lumped.external_force[static_cast<std::size_t>(n)].y() -= q * share;
    }
    FemState state = make_rest_state(model);
    ExplicitSolver solver(model, make_constraints(model.mesh, box, "test"), 0.0,
                          Damping{NodalDamping{0.0, 0.8}, 0.0}, models_of(model));
    const double dt = solver.stable_time_step(state, 0.5);
    for (int i = 0; i < 20000; ++i) solver.step(state, dt);
    double speed = 0.0;
    for (const Vec2& v : state.velocity) speed = std::max(speed, v.norm());
    const double elements = chequerboard(state.element_pore_pressure, nx - 1, ny - 1, q);
    const double nodes = chequerboard(state.pore_pressure, nx, ny, q);
    const double largest = *std::ranges::max_element(state.element_pore_pressure);
    std::printf(
        "strip load, h = %.1f m: largest p %.1f kPa; p99 of the chequerboard %.2f %% of q in "
        "the elements, %.2f %% at the nodes; largest speed left %.2e m/s\n",
        h, largest / 1e3, 100.0 * elements, 100.0 * nodes, speed);
    if (std::getenv("SLIDE_DUMP")) {
      for (int j = ny; j >= ny - 6; --j) {
        for (int i = nx / 2 - 6; i <= nx / 2 + 6; ++i) {
          std::printf("%7.1f",
                      state.pore_pressure[static_cast<std::size_t>(j * (nx + 1) + i)] / 1e3);
        }
        std::printf("\n");
      }
    }
    EXPECT_LT(speed, 1e-4);  // at rest (the load's waves gave ~1 m/s)
    EXPECT_LT(elements, 0.05);
    EXPECT_LT(nodes, 0.05);
  }
}

}  // namespace
}  // namespace slide::fem
