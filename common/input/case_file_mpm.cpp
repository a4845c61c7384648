// The case reader's [mpm] table: grid, algorithms, run and pure-MPM settings.
// Section, the ranges and the shared readers are in case_file_reader.hpp.
#include <cmath>

#include "common/input/case_file_reader.hpp"

namespace slide::case_reader {

namespace {

void read_domain(const Section& s, MpmSpec& mpm) {
  const NodeReader& reader = s.reader();
  const auto& corners = reader.array(s.node("domain"), s.dotted("domain"));
  if (corners.size() != 2) {
    s.fail("domain",
           fmt::format("expected [[xmin, ymin], [xmax, ymax]], found {} items", corners.size()));
  }
  mpm.domain_min = reader.point(corners[0], s.dotted("domain") + "[0]");
  mpm.domain_max = reader.point(corners[1], s.dotted("domain") + "[1]");
  if (!(mpm.domain_max.x() > mpm.domain_min.x() && mpm.domain_max.y() > mpm.domain_min.y())) {
    s.fail("domain", fmt::format("the upper-right corner {} must lie above and right of the "
                                 "lower-left corner {}",
                                 format_point(mpm.domain_max), format_point(mpm.domain_min)));
  }
}

void check_cells(const Section& s, const MpmSpec& mpm) {
  const Vec2 extent = mpm.domain_max - mpm.domain_min;
  for (int axis = 0; axis < 2; ++axis) {
    const double cells = extent[axis] / mpm.cell_size;
    if (std::abs(cells - std::round(cells)) > 1e-9 * cells || std::round(cells) < 1.0) {
      s.fail("cell_size",
             fmt::format("{} m does not divide the domain into whole cells ({}: {} m / {} m = "
                         "{:.6g} cells)",
                         mpm.cell_size, axis == 0 ? "x" : "y", extent[axis], mpm.cell_size, cells));
    }
  }
}

/// The grid: its corners and cell size, which must divide it and hold the initial body.
void read_grid(const Section& s, const MeshSpec& mesh, MpmSpec& mpm) {
  read_domain(s, mpm);
  mpm.cell_size = s.number("cell_size", positive("m"));
  check_cells(s, mpm);
  if (const auto box = body_box(mesh)) {
    const bool inside = (box->first.array() >= mpm.domain_min.array()).all() &&
                        (box->second.array() <= mpm.domain_max.array()).all();
    if (!inside) {
      s.fail("domain", fmt::format("the grid {}–{} does not contain the initial body {}–{}",
                                   format_point(mpm.domain_min), format_point(mpm.domain_max),
                                   format_point(box->first), format_point(box->second)));
    }
  }
}

/// The algorithm choices: shape functions, update scheme, velocity transfer, smoothing.
void read_algorithms(const Section& s, const MaterialTable& materials, MpmSpec& mpm) {
  mpm.shape_function =
      s.choice("shape_function", shape_function_names, std::optional(ShapeFunction::gimp));
  mpm.update_scheme =
      s.choice("update_scheme", update_scheme_names, std::optional(UpdateScheme::musl));
  mpm.velocity_transfer = s.choice("velocity_transfer", velocity_transfer_names,
                                   std::optional(VelocityTransfer::flip_pic));
  // pic_fraction is the tuning key of flip-pic: accepted and ignored with apic (the
  // policy at the top of case_file.cpp), so a case switches transfer with one line.
  mpm.pic_fraction = s.number(
      "pic_fraction", Range{.min = 0.0, .min_closed = true, .max = 1.0, .max_closed = true}, 0.0);
  // On by default where it matters: plastic flow (ψ = 0 is isochoric) locks and
  // checkerboards; an elastic body does not need it (mpm/README.md, "Volumetric smoothing").
  const bool plastic = std::any_of(materials.begin(), materials.end(), [](const Material& m) {
    return m.model_of(Phase::mpm) != MaterialModel::linear_elastic;
  });
  mpm.volumetric_smoothing =
      s.choice("volumetric_smoothing", volumetric_smoothing_names,
               std::optional(plastic ? VolumetricSmoothing::cell : VolumetricSmoothing::none));
}

/// The run: its end, outputs, time step, boundaries, damping and when it stops early.
void read_run(const Section& s, const TransferSpec& transfer, MpmSpec& mpm) {
  // The MPM phase continues the clock from t_T: it must end after every transfer time.
  double latest_transfer = transfer.main_time;
  for (double t : transfer.sweep_times) latest_transfer = std::max(latest_transfer, t);
  mpm.end_time = s.number(
      "end_time", Range{.min = latest_transfer,
                        .unit = "s",
                        .note = latest_transfer > 0.0 ? "after the latest transfer time" : ""});
  read_schedule_and_step(s, mpm);
  mpm.friction_coefficient = s.number("friction_coefficient", non_negative(), 0.0);
  mpm.boundaries = read_boundaries(s, "boundaries", grid_boundaries, friction_problem(s));
  mpm.local_damping = s.number("local_damping", unit_interval_open_above(), 0.0);
  mpm.particle_exit =
      s.choice("particle_exit", particle_exit_names, std::optional(ParticleExit::freeze));
  mpm.rest_threshold = s.number("rest_threshold", non_negative(), 0.0);
  mpm.rest_duration = s.number("rest_duration", non_negative("s"), 0.0);
  mpm.speed_limit_factor = s.number("speed_limit_factor", positive(), mpm.speed_limit_factor);
}

/// Pure MPM (no particle file): particles per cell and how the initial stress is set.
void read_pure_mpm(const Section& s, MpmSpec& mpm) {
  std::tie(mpm.particles_x, mpm.particles_y) =
      read_particle_layout(s, "particles_per_cell", mpm.particles_x);
  mpm.initial_stress =
      s.choice("initial_stress", initial_stress_names, std::optional(InitialStress::k0));
  if (mpm.initial_stress == InitialStress::gravity) {
    mpm.gravity_stage_duration = s.number(
        "gravity_stage_duration",
        Range{.min = 0.0, .unit = "s", .note = "required by initial_stress = \"gravity\""});
  } else {
    mpm.gravity_stage_duration = s.number("gravity_stage_duration", non_negative("s"), 0.0);
  }
  mpm.gravity_stage_damping = s.number("gravity_stage_damping", unit_interval_open_above(), 0.0);
}

/// [mpm.pore_water] and [mpm.reservoir] (docs/method.md §10).
void read_pore_water_and_reservoir(const Section& s, MpmSpec& mpm) {
  if (const auto pore =
          s.optional_table("pore_water", Section::Keys{"pore_pressure", "bulk_modulus"})) {
    const std::string mode = pore->string("pore_pressure", "frozen");
    if (mode != "frozen" && mode != "undrained") {
      pore->reader().inadmissible(pore->node("pore_pressure"), pore->dotted("pore_pressure"),
                                  fmt::format("\"{}\"", mode), "\"frozen\" or \"undrained\"");
    }
    mpm.undrained_pore_pressure = mode == "undrained";
    mpm.water_bulk_modulus = pore->number("bulk_modulus", positive("Pa"), mpm.water_bulk_modulus);
  }
  if (const auto water =
          s.optional_table("reservoir", Section::Keys{"level", "density", "extent"})) {
    // The water outside the body; its level may stand above the grid (a deep reservoir).
    mpm.reservoir_level = water->number("level", any_number());
    mpm.water_density = water->number("density", positive("kg/m³"), mpm.water_density);
    if (water->has("extent")) {
      const Vec2 extent = water->reader().point(water->node("extent"), water->dotted("extent"));
      if (!(extent.y() > extent.x()))
        water->fail("extent", "expected [x_min, x_max], x_min < x_max");
      mpm.reservoir_x_min = extent.x();
      mpm.reservoir_x_max = extent.y();
    }
  }
}

/// [[mpm.recorders]].
std::vector<ParticleRecorderSpec> read_particle_recorders(const Section& s) {
  std::vector<ParticleRecorderSpec> recorders;
  std::vector<std::string> taken;
  for (const Section& r : s.tables("recorders", Section::Keys{"name", "points", "every"})) {
    ParticleRecorderSpec spec;
    spec.name = read_recorder_name(r, taken);
    spec.points = read_points(r, "points");
    spec.every = r.number("every", non_negative("s"), 0.0);
    taken.push_back(spec.name);
    recorders.push_back(std::move(spec));
  }
  return recorders;
}

}  // namespace

MpmSpec read_mpm(const Section& root, const MaterialTable& materials, const MeshSpec& mesh,
                 const TransferSpec& transfer) {
  const Section s = root.table("mpm", Section::Keys{"domain",
                                                    "cell_size",
                                                    "shape_function",
                                                    "update_scheme",
                                                    "velocity_transfer",
                                                    "pic_fraction",
                                                    "volumetric_smoothing",
                                                    "end_time",
                                                    "checkpoint_times",
                                                    "checkpoint_every",
                                                    "output_every",
                                                    "vtk_every",
                                                    "courant",
                                                    "time_step",
                                                    "boundaries",
                                                    "friction_coefficient",
                                                    "local_damping",
                                                    "particle_exit",
                                                    "rest_threshold",
                                                    "rest_duration",
                                                    "speed_limit_factor",
                                                    "particles_per_cell",
                                                    "initial_stress",
                                                    "gravity_stage_duration",
                                                    "gravity_stage_damping",
                                                    "reservoir",
                                                    "pore_water",
                                                    "recorders"});
  MpmSpec mpm;
  // Order matters: of several faults, the first one read is the one reported.
  read_grid(s, mesh, mpm);
  read_algorithms(s, materials, mpm);
  read_run(s, transfer, mpm);
  read_pure_mpm(s, mpm);
  read_pore_water_and_reservoir(s, mpm);
  if (s.has("recorders")) mpm.recorders = read_particle_recorders(s);
  return mpm;
}

}  // namespace slide::case_reader
