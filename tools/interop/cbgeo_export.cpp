#include "tools/interop/cbgeo_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <variant>

#include <fmt/format.h>
#include <hdf5.h>
#include <nlohmann/json.hpp>

#include "common/base/error.hpp"
#include "common/base/types.hpp"
#include "common/io/atomic_file.hpp"
#include "common/run/stage.hpp"

namespace slide::interop {
namespace {

using Json = nlohmann::ordered_json;

/// CB-Geo's node sets of the grid's sides, in entity_sets.json and the constraints.
enum NodeSetId { left_set = 0, right_set = 1, base_set = 2, top_set = 3 };

/// Numbers written with 17 significant digits: the files carry doubles exactly.
std::string exact(double value) {
  return fmt::format("{:.17g}", value);
}

struct Grid {
  Vec2 origin = Vec2::Zero();
  double h = 1.0;
  long nx = 0;  ///< cells along x
  long ny = 0;
  long nodes() const { return (nx + 1) * (ny + 1); }
  long node(long i, long j) const { return i + (nx + 1) * j; }
};

Grid grid_of(const MpmSpec& mpm) {
  Grid g;
  g.origin = mpm.domain_min;
  g.h = mpm.cell_size;
  const Vec2 extent = mpm.domain_max - mpm.domain_min;
  g.nx = std::lround(extent.x() / g.h);
  g.ny = std::lround(extent.y() / g.h);
  return g;
}

std::string mesh_text(const Grid& g) {
  std::string text = fmt::format(
      "# CB-Geo MPM mesh (Ascii2D, ED2Q4): {} x {} cells of {} m from ({}, {}); written by "
      "mpm2cbgeo\n{} {}\n",
      g.nx, g.ny, g.h, g.origin.x(), g.origin.y(), g.nodes(), g.nx * g.ny);
  for (long j = 0; j <= g.ny; ++j) {
    for (long i = 0; i <= g.nx; ++i) {
      text += exact(g.origin.x() + static_cast<double>(i) * g.h) + " " +
              exact(g.origin.y() + static_cast<double>(j) * g.h) + "\n";
    }
  }
  for (long j = 0; j < g.ny; ++j) {
    for (long i = 0; i < g.nx; ++i) {
      text += fmt::format("{} {} {} {}\n", g.node(i, j), g.node(i + 1, j), g.node(i + 1, j + 1),
                          g.node(i, j + 1));
    }
  }
  return text;
}

Json entity_sets(const Grid& g) {
  std::vector<long> left, right, base, top;
  for (long j = 0; j <= g.ny; ++j) {
    left.push_back(g.node(0, j));
    right.push_back(g.node(g.nx, j));
  }
  for (long i = 0; i <= g.nx; ++i) {
    base.push_back(g.node(i, 0));
    top.push_back(g.node(i, g.ny));
  }
  Json sets = Json::array();
  sets.push_back({{"id", left_set}, {"set", left}});
  sets.push_back({{"id", right_set}, {"set", right}});
  sets.push_back({{"id", base_set}, {"set", base}});
  sets.push_back({{"id", top_set}, {"set", top}});
  return {{"node_sets", sets}};
}

/// The side's set and the direction of its normal (0: x, 1: y) and the sign of the
/// outward normal.
struct Side {
  const char* name;
  NodeSetId set;
  int normal_dir;
  int outward_sign;
};
constexpr Side sides[] = {{"left", left_set, 0, -1},
                          {"right", right_set, 0, 1},
                          {"base", base_set, 1, -1},
                          {"top", top_set, 1, 1}};

Json boundary_conditions(const MpmSpec& mpm, std::vector<std::string>& notes) {
  Json velocity = Json::array();
  Json friction = Json::array();
  for (const Side& side : sides) {
    const auto it = mpm.boundaries.find(side.name);
    const BoundaryCondition condition =
        it == mpm.boundaries.end() ? BoundaryCondition::free : it->second;
    switch (condition) {
      case BoundaryCondition::free:
        break;
      case BoundaryCondition::roller:
        velocity.push_back({{"nset_id", side.set}, {"dir", side.normal_dir}, {"velocity", 0.0}});
        break;
      case BoundaryCondition::fixed:
        velocity.push_back({{"nset_id", side.set}, {"dir", 0}, {"velocity", 0.0}});
        velocity.push_back({{"nset_id", side.set}, {"dir", 1}, {"velocity", 0.0}});
        break;
      case BoundaryCondition::friction:
        // The normal velocity held at zero, the tangential one limited by μ|a_n|dt when
        // the node presses on the side (CB-Geo's friction constraint).
        velocity.push_back({{"nset_id", side.set}, {"dir", side.normal_dir}, {"velocity", 0.0}});
        friction.push_back({{"nset_id", side.set},
                            {"dir", side.normal_dir},
                            {"sign_n", side.outward_sign},
                            {"friction", mpm.friction_coefficient}});
        break;
    }
  }
  if (!friction.empty()) {
    notes.push_back(
        fmt::format("friction: CB-Geo's friction constraint with μ = {} limits the "
                    "nodal tangential velocity, as the project's Coulomb base does",
                    mpm.friction_coefficient));
  }
  Json conditions = {{"velocity_constraints", velocity}};
  if (!friction.empty()) conditions["friction_constraints"] = friction;
  return conditions;
}

Json material_json(const Material& m, int id, std::vector<std::string>& notes) {
  const MaterialModel model = m.model_of(Phase::mpm);
  if (model == MaterialModel::linear_elastic) {
    return {{"id", id},
            {"type", "LinearElastic2D"},
            {"density", m.density},
            {"youngs_modulus", m.youngs_modulus},
            {"poisson_ratio", m.poisson_ratio}};
  }
  if (model == MaterialModel::pressure_independent_multi_yield) {
    notes.push_back(fmt::format(
        "material {} ('{}'): CB-Geo has no pressure-independent multi-yield model: written as "
        "MohrCoulomb2D with its φ = {}°, c = {} Pa (the nested surfaces and the frozen strength "
        "are lost)",
        id, m.name, m.friction_angle, m.cohesion));
  }
  // No tension cut-off (T = +inf) is the apex c·cot φ for CB-Geo, which needs a number.
  double cutoff = m.tension_cutoff;
  if (!std::isfinite(cutoff)) {
    const double phi = m.friction_angle * std::numbers::pi / 180.0;
    cutoff = phi > 0.0 ? m.cohesion / std::tan(phi) : 1e15;
  }
  return {{"id", id},
          {"type", "MohrCoulomb2D"},
          {"density", m.density},
          {"youngs_modulus", m.youngs_modulus},
          {"poisson_ratio", m.poisson_ratio},
          {"softening", false},
          {"friction", m.friction_angle},
          {"dilation", m.dilation_angle},
          {"cohesion", m.cohesion},
          {"residual_friction", m.friction_angle},
          {"residual_dilation", m.dilation_angle},
          {"residual_cohesion", m.cohesion},
          {"peak_pdstrain", 0.0},
          {"residual_pdstrain", 0.0},
          {"tension_cutoff", cutoff}};
}

/// Particle i as a row of CB-Geo's particle table, with CB-Geo's id and volume.
CbGeoParticle table_row(const Particles& p, std::size_t i, long id, double volume, const Grid& g) {
  CbGeoParticle row;
  row.id = id;
  row.mass = p.mass[i];
  row.volume = volume;
  for (int k = 0; k < 2; ++k) {
    row.coordinates[k] = p.coordinates[i][k];
    row.displacement[k] = p.displacement[i][k];
    row.velocity[k] = p.velocity[i][k];
    // CB-Geo's natural size: the particle's share of the cell's natural length 2.
    row.natural_size[k] = 2.0 * p.size[i][k] / g.h;
  }
  const Vec4& s = p.stress[i];
  const Vec4& e = p.strain[i];
  row.stress[0] = s[0];
  row.stress[1] = s[1];
  row.stress[2] = s[2];
  row.stress[3] = s[3];
  row.strain[0] = e[0];
  row.strain[1] = e[1];
  row.strain[2] = e[2];
  row.strain[3] = e[3];
  row.volumetric_strain = e[0] + e[1] + e[2];
  const Vec2 local = (p.coordinates[i] - g.origin) / g.h;
  const long ci = std::clamp(static_cast<long>(std::floor(local.x())), 0L, g.nx - 1);
  const long cj = std::clamp(static_cast<long>(std::floor(local.y())), 0L, g.ny - 1);
  row.cell = ci + g.nx * cj;
  row.material = static_cast<std::uint32_t>(p.material_id[i]);
  return row;
}

/// The Courant step of the particles, as mpm-solve takes it at the start of a run
/// (mpm/README.md, "Time step"): C h / max c_p, c_p² = M V_p / m_p.
double courant_step(const MpmSpec& mpm, double courant, const Particles& p,
                    const MaterialTable& materials) {
  if (mpm.time_step > 0.0) return mpm.time_step;
  double fastest = 0.0;
  for (std::size_t i = 0; i < p.count(); ++i) {
    const Material& m = materials[static_cast<std::size_t>(p.material_id[i])];
    fastest = std::max(fastest, m.p_wave_modulus() * p.volume[i] / p.mass[i]);
  }
  if (!(fastest > 0.0)) throw Error("mpm2cbgeo: no particle with a finite wave speed");
  return courant * mpm.cell_size / std::sqrt(fastest);
}

/// Every particle inside the grid: CB-Geo stops at the first it cannot locate.
void check_inside_grid(const Particles& p, const MpmSpec& mpm) {
  const Vec2 lo = mpm.domain_min;
  const Vec2 hi = mpm.domain_max;
  for (std::size_t i = 0; i < p.count(); ++i) {
    const Vec2& x = p.coordinates[i];
    if (!((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all())) {
      throw Error(
          "mpm2cbgeo: particle {} at ({}, {}) m is outside the grid ({}, {})–({}, {}) m "
          "of the case's mpm.domain: CB-Geo cannot locate it",
          p.id[i], x.x(), x.y(), lo.x(), lo.y(), hi.x(), hi.y());
    }
  }
}

/// What the particle files hold, for mpm.json and the notes.
struct ParticleFiles {
  Json generators = Json::array();
  Json materials = Json::array();
  double largest_volume_change = 0.0;
  double speed = 0.0;
  double largest_strain = 0.0;
};

/// The particle files: material by material (one CB-Geo file generator each), file order
/// within; their stresses and volumes in CB-Geo's particle order; the resume table.
ParticleFiles write_particle_files(const Particles& p, const MaterialTable& materials,
                                   const Grid& g, CbGeoInput& input) {
  std::vector<std::vector<std::size_t>> by_material(materials.size());
  for (std::size_t i = 0; i < p.count(); ++i) {
    by_material[static_cast<std::size_t>(p.material_id[i])].push_back(i);
  }
  std::string stresses = fmt::format(
      "# particle stresses, Pa, tension positive: xx yy zz xy yz xz, in CB-Geo's particle order\n"
      "{}\n",
      p.count());
  std::string volumes = "# particle id (CB-Geo's, 0-based) and volume, m^3 per m\n";
  ParticleFiles files;
  long cbgeo_id = 0;
  for (std::size_t m = 0; m < materials.size(); ++m) {
    if (by_material[m].empty()) continue;
    const double density = materials[m].density;
    const std::string name = fmt::format("particles-{}.txt", m);
    std::string coordinates = fmt::format("# particles of material {} ('{}'): x y, m\n{}\n", m,
                                          materials[m].name, by_material[m].size());
    for (const std::size_t i : by_material[m]) {
      coordinates += exact(p.coordinates[i].x()) + " " + exact(p.coordinates[i].y()) + "\n";
      const Vec4& s = p.stress[i];
      stresses +=
          fmt::format("{} {} {} {} 0 0\n", exact(s[0]), exact(s[1]), exact(s[2]), exact(s[3]));
      const double volume = p.mass[i] / density;
      volumes += fmt::format("{} {}\n", cbgeo_id, exact(volume));
      input.resume_particles.push_back(table_row(p, i, cbgeo_id, volume, g));
      ++cbgeo_id;
      files.largest_volume_change =
          std::max(files.largest_volume_change, std::abs(volume / p.volume[i] - 1.0));
      files.speed = std::max(files.speed, p.velocity[i].norm());
      files.largest_strain = std::max(files.largest_strain, p.strain[i].cwiseAbs().maxCoeff());
    }
    input.files.emplace_back(name, coordinates);
    files.generators.push_back({{"generator",
                                 {{"type", "file"},
                                  {"io_type", "Ascii2D"},
                                  {"location", name},
                                  {"check_duplicates", true},
                                  {"pset_id", static_cast<int>(m)},
                                  {"particle_type", "P2D"},
                                  {"material_id", static_cast<int>(m)}}}});
    files.materials.push_back(material_json(materials[m], static_cast<int>(m), input.notes));
  }
  input.files.emplace_back("particles-stresses.txt", stresses);
  input.files.emplace_back("particles-volumes.txt", volumes);
  return files;
}

/// What the particle files cannot carry.
void add_particle_notes(const ParticleFiles& files, std::vector<std::string>& notes) {
  if (files.largest_volume_change > 1e-12) {
    notes.push_back(
        fmt::format("volumes: written as M_p/ρ so that CB-Geo's masses are the "
                    "particles'; they differ from the particles' V_p by up to {:.3g} %",
                    100.0 * files.largest_volume_change));
  }
  if (files.speed > 0.0 || files.largest_strain > 0.0) {
    notes.push_back(fmt::format(
        "velocities (fastest {:.3g} m/s) and strains: carried by the resume file; CB-Geo's ASCII "
        "input has neither, so with analysis.resume.resume = false the particles start at rest "
        "and unstrained",
        files.speed));
  }
  notes.push_back(
      "plastic state: CB-Geo initialises its Mohr–Coulomb state variables, the "
      "accumulated plastic strains are not carried (no softening, so no effect)");
}

/// The rows an mpm checkpoint's /solver record says mpm-solve froze at the grid's edge
/// (0 in a particle file).
std::int64_t frozen_rows(const SolverSettings& solver) {
  const auto it = solver.find("frozen_particles");
  if (it == solver.end()) return 0;
  if (const auto* count = std::get_if<std::int64_t>(&it->second)) return *count;
  if (const auto* count = std::get_if<double>(&it->second)) return std::llround(*count);
  return 0;
}

/// The particles' state that neither the ASCII files nor the resume table hold.
void add_state_notes(const ParticleCheckpoint& checkpoint, std::vector<std::string>& notes) {
  const Particles& p = checkpoint.particles;
  double largest_pore_pressure = 0.0;
  for (const double u : p.pore_pressure)
    largest_pore_pressure = std::max(largest_pore_pressure, std::abs(u));
  if (largest_pore_pressure > 0.0) {
    notes.push_back(fmt::format(
        "pore pressures (up to {:.6g} Pa): CB-Geo's single-phase MPMExplicit2D has none; the "
        "stresses are written as they are",
        largest_pore_pressure));
  }
  if (const std::int64_t frozen = frozen_rows(checkpoint.solver); frozen > 0) {
    notes.push_back(fmt::format(
        "frozen particles: {} that mpm-solve froze at the grid's edge are written as ordinary "
        "particles, which CB-Geo moves again",
        frozen));
  }
}

/// What the case sets outside [mpm] that the MPM phase runs with and mpm.json does not
/// hold: a turned gravity and the base motion.
void add_case_notes(const Case& c, const ParticleCheckpoint& checkpoint,
                    std::vector<std::string>& notes) {
  if (c.gravity != gravity_vector()) {
    const double angle = std::atan2(c.gravity.x(), -c.gravity.y()) * 180.0 / std::numbers::pi;
    notes.push_back(fmt::format(
        "gravity_angle: the case turns gravity by {:.6g}° to ({:.6g}, {:.6g}) m/s²; mpm.json's "
        "gravity is (0, {}) m/s²",
        angle, c.gravity.x(), c.gravity.y(), -gravity_acceleration));
  }
  if (checkpoint.motion) {
    const CheckpointMotion& m = *checkpoint.motion;
    const double time = checkpoint.header.time;
    const Vec2 base = base_position(m, grid_motion(m), time);
    notes.push_back(fmt::format(
        "base motion: the file's /motion ({} samples every {:.6g} s from t = {} s, {} base) is "
        "not written: CB-Geo's grid stays at rest at mpm.domain, while mpm-solve moves it with "
        "the base (by ({:.6g}, {:.6g}) m at t = {} s)",
        m.acceleration.size(), m.step, m.start_time, m.base, base.x(), base.y(), time));
  } else if (c.fem.motion) {
    notes.push_back(
        "base motion: the case's [fem.motion] is not written (the particle file has no "
        "/motion either): CB-Geo's grid stays at rest");
  }
}

/// At most this many CB-Geo outputs: each is an HDF5 file of the whole particle table
/// (416 B a particle: 32,000 particles make 13 MB a file). A run of 10⁵ outputs is 100
/// times the 0.1 s outputs of a 100 s runout; beyond it the cadence is a mistake.
constexpr double max_outputs = 1e5;

/// The cadence of CB-Geo's outputs, s, and what gave it (an option, a key of the case, or
/// nothing: the end time only).
struct OutputCadence {
  double every = 0.0;
  std::string source;
};

OutputCadence output_cadence(const Case& c, const CbGeoExportOptions& options) {
  if (options.output_every > 0.0) return {options.output_every, "--output-every"};
  if (c.mpm.checkpoint_every > 0.0) return {c.mpm.checkpoint_every, "mpm.checkpoint_every"};
  return {};
}

/// CB-Geo's step and step count (into `input`) and its output interval in steps. CB-Geo
/// writes its state at the steps that are multiples of output_steps and, resumed from
/// step 0, runs steps 1 … nsteps − 1: the output interval is shortened to divide the
/// duration, the step is the Courant step shortened to divide the interval, and
/// nsteps − 1 steps make the duration, so that the last output is the end time. A cadence
/// shorter than the step, more than max_outputs outputs or run::max_steps steps are
/// refused: every number of mpm.json must be a finite, meaningful one.
long choose_steps(const Case& c, const CbGeoExportOptions& options,
                  const ParticleCheckpoint& checkpoint, CbGeoInput& input) {
  // CB-Geo's clock starts at 0 at the particles' time.
  const double start = checkpoint.header.time;
  const double end = options.end_time > 0.0 ? options.end_time : c.mpm.end_time;
  if (!(end > start)) {
    throw Error("mpm2cbgeo: end time {} s is not after the particles' time {} s (give --end-time)",
                end, start);
  }
  if (!(options.courant > 0.0 && options.courant <= 1.0)) {
    throw Error("--courant {}: expected a Courant number in (0, 1]", options.courant);
  }
  const double duration = end - start;
  const double courant =
      courant_step(c.mpm, options.courant, checkpoint.particles, checkpoint.materials);
  const std::string step_source =
      c.mpm.time_step > 0.0
          ? std::string("the case's mpm.time_step")
          : fmt::format("the Courant step C h / max c_p at --courant {}", options.courant);
  const std::string run_source =
      fmt::format("CB-Geo's fixed step is {}, the run {} s long (t = {} to {} s, {})", step_source,
                  duration, start, end, options.end_time > 0.0 ? "--end-time" : "mpm.end_time");
  run::check_step_count(duration, courant, run_source);
  const OutputCadence cadence = output_cadence(c, options);
  if (!cadence.source.empty() && cadence.every < courant) {
    // The least cadence to suggest: the step rounded up to three significant digits.
    const double unit = std::pow(10.0, std::floor(std::log10(courant)) - 2.0);
    throw Error(
        "{} = {} s is shorter than CB-Geo's time step {:.6g} s, {}: CB-Geo writes its state at "
        "most once a step (give --output-every {:.3g} or more)",
        cadence.source, cadence.every, courant, step_source, std::ceil(courant / unit) * unit);
  }
  const double asked = cadence.source.empty() ? duration : std::min(duration, cadence.every);
  const double outputs = std::ceil(duration / asked - 1e-9);
  if (!(outputs <= max_outputs)) {
    throw Error(
        "{} = {} s makes {:.3g} outputs over the {} s from t = {} to {} s, more than {:.0e} "
        "(each is a file of every particle, {:.3g} MB): give a longer cadence",
        cadence.source, cadence.every, outputs, duration, start, end, max_outputs,
        static_cast<double>(checkpoint.particles.count() * sizeof(CbGeoParticle)) / 1e6);
  }
  const double every = duration / std::max(outputs, 1.0);
  const double per_output = std::max(1.0, std::ceil(every / courant - 1e-9));
  input.time_step = every / per_output;
  run::check_step_count(duration, input.time_step, run_source);
  input.steps = std::lround(duration / input.time_step) + 1;
  return static_cast<long>(per_output);
}

/// The algorithms CB-Geo has not, and what they are written as.
void add_scheme_notes(const MpmSpec& mpm, const std::string& scheme, double time_step,
                      std::vector<std::string>& notes) {
  if (mpm.update_scheme == UpdateScheme::musl || scheme == "usf") {
    notes.push_back(fmt::format("update scheme: {} written as CB-Geo's {} (CB-Geo has USF and USL)",
                                mpm.update_scheme == UpdateScheme::musl ? "MUSL" : "USL",
                                scheme == "usf" ? "USF" : "USL"));
  }
  if (mpm.shape_function == ShapeFunction::gimp) {
    notes.push_back(
        "shape functions: uGIMP written as CB-Geo's linear ED2Q4 cells (its GIMP "
        "element needs a 16-node connectivity this export does not write)");
  }
  if (mpm.velocity_transfer == VelocityTransfer::apic) {
    notes.push_back(
        "velocity transfer: APIC written as FLIP (CB-Geo has FLIP and PIC; the particles' "
        "affine velocities are dropped)");
  } else if (mpm.pic_fraction > 0.0 && mpm.pic_fraction < 1.0) {
    notes.push_back(fmt::format(
        "velocity transfer: the FLIP/PIC blend mpm.pic_fraction = {} written as FLIP (CB-Geo's "
        "velocity_update is all PIC or all FLIP)",
        mpm.pic_fraction));
  }
  if (mpm.time_step == 0.0) {
    notes.push_back(fmt::format(
        "time step: mpm-solve's Courant step, renewed as the particles deform, written as "
        "CB-Geo's fixed dt = {:.6g} s (--courant)",
        time_step));
  }
  if (mpm.volumetric_smoothing == VolumetricSmoothing::cell) {
    notes.push_back("cell volumetric smoothing: written as CB-Geo's pressure_smoothing");
  }
}

/// How a run stops and what it writes, where CB-Geo has no equivalent.
void add_run_control_notes(const MpmSpec& mpm, std::vector<std::string>& notes) {
  if (mpm.particle_exit == ParticleExit::freeze) {
    notes.push_back(
        "mpm.particle_exit = \"freeze\": CB-Geo removes the particles that leave the grid "
        "(locate_particles: false)");
  }
  if (mpm.rest_threshold > 0.0 && mpm.rest_duration > 0.0) {
    notes.push_back(fmt::format(
        "rest stop (mpm.rest_threshold = {} for mpm.rest_duration = {} s): CB-Geo has none and "
        "runs to the end time",
        mpm.rest_threshold, mpm.rest_duration));
  }
  notes.push_back(
      fmt::format("mpm.speed_limit_factor = {}: CB-Geo has no instability guard, a blow-up runs on",
                  mpm.speed_limit_factor));
  if (!mpm.checkpoint_times.empty()) {
    notes.push_back(fmt::format(
        "mpm.checkpoint_times: CB-Geo writes its state at the regular cadence only, not at the {} "
        "listed time(s)",
        mpm.checkpoint_times.size()));
  }
}

/// The first number of `json` that is not finite, as "key.key[i]" below `path`, or
/// nothing: nlohmann writes NaN and ±inf as null, which CB-Geo would misread.
std::optional<std::string> non_finite_number(const Json& json, const std::string& path) {
  if (json.is_number_float() && !std::isfinite(json.get<double>())) {
    return fmt::format("{} = {}", path, json.get<double>());
  }
  if (json.is_object()) {
    for (auto it = json.begin(); it != json.end(); ++it) {
      if (auto found = non_finite_number(*it, path.empty() ? it.key() : path + "." + it.key()))
        return found;
    }
  } else if (json.is_array()) {
    for (std::size_t i = 0; i < json.size(); ++i) {
      if (auto found = non_finite_number(json[i], fmt::format("{}[{}]", path, i))) return found;
    }
  }
  return std::nullopt;
}

/// `json` as the text of file `name`; Error before anything is written if a number is not
/// finite.
std::string json_text(const Json& json, const std::string& name) {
  if (const auto found = non_finite_number(json, "")) {
    throw Error("{}: {}, expected a finite number (nothing written)", name, *found);
  }
  return json.dump(2) + "\n";
}

/// mpm.json: mesh and particle files, materials, gravity, the analysis, its outputs.
Json analysis_json(const Case& c, const ParticleCheckpoint& checkpoint, const ParticleFiles& files,
                   const std::string& scheme, const CbGeoInput& input, long output_steps) {
  Json mpm;
  mpm["title"] = fmt::format("{}: particles at t = {} s from {}", c.name, checkpoint.header.time,
                             checkpoint.header.producer);
  mpm["mesh"] = {{"mesh", "mesh.txt"},
                 {"entity_sets", "entity_sets.json"},
                 {"particles_volumes", "particles-volumes.txt"},
                 {"particles_stresses", "particles-stresses.txt"},
                 {"io_type", "Ascii2D"},
                 {"check_duplicates", true},
                 {"isoparametric", false},
                 {"node_type", "N2D"},
                 {"cell_type", "ED2Q4"},
                 {"boundary_conditions", Json()}};
  mpm["particles"] = files.generators;
  mpm["materials"] = files.materials;
  mpm["external_loading_conditions"] = {{"gravity", {0.0, -gravity_acceleration}}};
  mpm["analysis"] = {
      {"type", "MPMExplicit2D"},
      {"mpm_scheme", scheme},
      {"locate_particles", false},
      {"dt", input.time_step},
      {"nsteps", input.steps},
      {"velocity_update",
       c.mpm.velocity_transfer == VelocityTransfer::flip_pic && c.mpm.pic_fraction >= 1.0},
      {"pressure_smoothing", c.mpm.volumetric_smoothing == VolumetricSmoothing::cell},
      {"damping", {{"type", "Cundall"}, {"damping_factor", c.mpm.local_damping}}},
      {"uuid", c.name},
      {"resume", {{"resume", true}, {"uuid", c.name}, {"step", 0}}}};
  mpm["post_processing"] = {
      {"path", "results/"}, {"output_steps", output_steps}, {"vtk", Json::array()}};
  return mpm;
}

}  // namespace

CbGeoInput export_cbgeo(const Case& c, const ParticleCheckpoint& checkpoint,
                        const CbGeoExportOptions& options) {
  const Particles& p = checkpoint.particles;
  if (p.count() == 0) throw Error("mpm2cbgeo: the particle file holds no particle");
  check_inside_grid(p, c.mpm);
  const Grid g = grid_of(c.mpm);
  CbGeoInput input;
  const ParticleFiles files = write_particle_files(p, checkpoint.materials, g, input);
  input.files.emplace_back("mesh.txt", mesh_text(g));
  input.files.emplace_back("entity_sets.json", json_text(entity_sets(g), "entity_sets.json"));
  add_particle_notes(files, input.notes);
  add_state_notes(checkpoint, input.notes);
  add_case_notes(c, checkpoint, input.notes);
  const long output_steps = choose_steps(c, options, checkpoint, input);
  add_scheme_notes(c.mpm, options.scheme, input.time_step, input.notes);
  add_run_control_notes(c.mpm, input.notes);
  Json mpm = analysis_json(c, checkpoint, files, options.scheme, input, output_steps);
  mpm["mesh"]["boundary_conditions"] = boundary_conditions(c.mpm, input.notes);
  input.files.emplace_back("mpm.json", json_text(mpm, "mpm.json"));
  // CB-Geo names its outputs with as many digits as nsteps has.
  const auto digits = static_cast<int>(std::to_string(input.steps).size());
  input.resume_file = fmt::format("results/{}/particles{:0{}d}.h5", c.name, 0, digits);
  return input;
}

void write_cbgeo_particles(const std::filesystem::path& path,
                           const std::vector<CbGeoParticle>& particles) {
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    // CB-Geo reads its table by field position: the names and order of its own output.
    const hid_t type = H5Tcreate(H5T_COMPOUND, sizeof(CbGeoParticle));
    std::size_t field = 0;
    const auto insert = [&](const std::string& name, std::size_t offset, hid_t member) {
      H5Tinsert(type, name.c_str(), offset, member);
      ++field;
    };
    const auto doubles = [&](std::initializer_list<const char*> names, std::size_t offset) {
      for (const char* name : names) {
        insert(name, offset, H5T_NATIVE_DOUBLE);
        offset += sizeof(double);
      }
    };
    insert("id", offsetof(CbGeoParticle, id), H5T_NATIVE_INT64);
    doubles({"mass", "volume", "pressure"}, offsetof(CbGeoParticle, mass));
    doubles({"coord_x", "coord_y", "coord_z"}, offsetof(CbGeoParticle, coordinates));
    doubles({"displacement_x", "displacement_y", "displacement_z"},
            offsetof(CbGeoParticle, displacement));
    doubles({"nsize_x", "nsize_y", "nsize_z"}, offsetof(CbGeoParticle, natural_size));
    doubles({"velocity_x", "velocity_y", "velocity_z"}, offsetof(CbGeoParticle, velocity));
    doubles({"stress_xx", "stress_yy", "stress_zz", "tau_xy", "tau_yz", "tau_xz"},
            offsetof(CbGeoParticle, stress));
    doubles({"strain_xx", "strain_yy", "strain_zz", "gamma_xy", "gamma_yz", "gamma_xz"},
            offsetof(CbGeoParticle, strain));
    doubles({"epsilon_v"}, offsetof(CbGeoParticle, volumetric_strain));
    insert("status", offsetof(CbGeoParticle, status), H5T_NATIVE_UINT8);
    insert("cell_id", offsetof(CbGeoParticle, cell), H5T_NATIVE_INT64);
    insert("material_id", offsetof(CbGeoParticle, material), H5T_NATIVE_UINT32);
    insert("nstate_vars", offsetof(CbGeoParticle, state_variables), H5T_NATIVE_UINT32);
    for (int k = 0; k < 20; ++k) {
      insert(fmt::format("svars_{}", k), offsetof(CbGeoParticle, state) + k * sizeof(double),
             H5T_NATIVE_DOUBLE);
    }
    const hsize_t rows = particles.size();
    const hid_t space = H5Screate_simple(1, &rows, nullptr);
    const hid_t file = H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    herr_t status = file < 0 ? -1 : 0;
    if (status >= 0) {
      const hid_t dataset =
          H5Dcreate2(file, "table", type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      status = dataset < 0
                   ? -1
                   : H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, particles.data());
      if (dataset >= 0) H5Dclose(dataset);
      if (H5Fclose(file) < 0) status = -1;
    }
    H5Sclose(space);
    H5Tclose(type);
    if (status < 0 || field != 53) {
      throw Error("{}: cannot write CB-Geo's particle table (disk full?)", path.string());
    }
  });
}

}  // namespace slide::interop
