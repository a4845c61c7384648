// The case reader's [fem] table: the stages, damping and boundaries of fem-solve.
// Section, the ranges and the shared readers are in case_file_reader.hpp.
#include <numbers>

#include "common/input/case_file_reader.hpp"

namespace slide::case_reader {

namespace {

const Section::Keys motion_component_keys{"source",         "units",     "amplitude",
                                          "peak_frequency", "peak_time", "frequency",
                                          "duration",       "taper",     "file"};

/// [fem.damping]: Rayleigh damping either as α_M, β_K or as a ratio ξ at two frequencies
/// (then α_M, β_K are derived), never both; Cundall's local α with either.
DampingSpec read_damping(const Section& s) {
  DampingSpec damping;
  damping.local = s.number("local", unit_interval_open_above(), 0.0);
  if (!s.has("ratio")) {
    s.reject("frequencies", fmt::format("only used with {}", s.dotted("ratio")));
    damping.rayleigh_mass = s.number("rayleigh_mass", non_negative("1/s"), 0.0);
    damping.rayleigh_stiffness = s.number("rayleigh_stiffness", non_negative("s"), 0.0);
    return damping;
  }
  for (std::string_view key : {"rayleigh_mass", "rayleigh_stiffness"}) {
    if (s.has(key)) {
      throw Error(
          "{}: {} and {}: two forms of the Rayleigh damping (give either ratio and frequencies "
          "or rayleigh_mass and rayleigh_stiffness)",
          s.where(key), s.dotted("ratio"), s.dotted(key));
    }
  }
  DampingRatio ratio;
  ratio.ratio = s.number("ratio", unit_interval_open_above());
  if (!s.has("frequencies")) s.missing("frequencies");
  const std::vector<double> f = s.numbers("frequencies", positive("Hz"), true);
  if (f.size() != 2) {
    s.fail("frequencies", fmt::format("expected [f1, f2] in Hz, found {} numbers", f.size()));
  }
  ratio.frequencies = {f[0], f[1]};
  const RayleighCoefficients coefficients = rayleigh_coefficients(ratio);
  damping.rayleigh_mass = coefficients.mass;
  damping.rayleigh_stiffness = coefficients.stiffness;
  damping.ratio = ratio;
  return damping;
}

/// The unit of a component's accelerations: "m/s2" (the default) or "g".
double read_acceleration_unit(const Section& s) {
  const std::string unit = s.string("units", "m/s2");
  if (unit == "m/s2") return 1.0;
  if (unit == "g") return gravity_acceleration;
  s.reader().inadmissible(s.node("units"), s.dotted("units"), fmt::format("\"{}\"", unit),
                          "one of: m/s2, g");
}

/// [fem.motion.horizontal] or [fem.motion.vertical].
MotionComponentSpec read_motion_component(const Section& s,
                                          const std::filesystem::path& case_folder) {
  MotionComponentSpec spec;
  spec.source = s.choice("source", motion_source_names, std::optional<MotionSource>());
  spec.scale = read_acceleration_unit(s);
  const auto only = [&](std::initializer_list<std::string_view> keys) {
    for (std::string_view key :
         {"amplitude", "peak_frequency", "peak_time", "frequency", "duration", "taper", "file"}) {
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
        s.reject(key, fmt::format("not used by source = \"{}\"", to_string(spec.source)));
      }
    }
  };
  switch (spec.source) {
    case MotionSource::ricker:
      only({"amplitude", "peak_frequency", "peak_time"});
      spec.amplitude = spec.scale * s.number("amplitude", any_number());
      spec.peak_frequency = s.number("peak_frequency", positive("Hz"));
      // The wavelet starts at τ = 0 and is cut at 2 τ_p: below τ_p = 1/f_p its start
      // jumps by more than 1e-3 of the peak.
      spec.peak_time = s.number(
          "peak_time", Range{.min = 1.0 / spec.peak_frequency,
                             .min_closed = true,
                             .unit = "s",
                             .note = "at least 1/peak_frequency, so that the wavelet starts "
                                     "from rest"});
      break;
    case MotionSource::sine:
      only({"amplitude", "frequency", "duration", "taper"});
      spec.amplitude = spec.scale * s.number("amplitude", any_number());
      spec.frequency = s.number("frequency", positive("Hz"));
      spec.duration = s.number("duration", positive("s"));
      spec.taper = s.number("taper",
                            Range{.min = 0.0,
                                  .min_closed = true,
                                  .max = 0.5 * spec.duration,
                                  .max_closed = true,
                                  .unit = "s",
                                  .note = "at most half the duration"},
                            std::min(1.0 / spec.frequency, 0.5 * spec.duration));
      break;
    case MotionSource::file: {
      only({"file"});
      const std::filesystem::path file = s.string("file");
      spec.file = file.is_absolute() ? file : case_folder / file;
      break;
    }
  }
  return spec;
}

/// [fem.motion]: the shaking and the boundaries it needs; `failure` the failure stage's
/// boundary table, which a compliant base and tied or viscous sides take over.
MotionSpec read_motion(const Section& s, const std::filesystem::path& case_folder,
                       const FemSpec& fem, const MeshSpec& mesh) {
  MotionSpec motion;
  motion.start_time = s.number("start_time", non_negative("s"), 0.0);
  if (!(motion.start_time < fem.end_time)) {
    s.fail("start_time",
           fmt::format("{} s is not before fem.end_time = {} s", motion.start_time, fem.end_time));
  }
  motion.base = s.choice("base", seismic_base_names, std::optional(SeismicBase::rigid));
  motion.lateral =
      s.choice("lateral", lateral_boundary_names, std::optional(LateralBoundary::boundaries));
  motion.baseline_correction = s.boolean("baseline_correction", true);
  if (motion.base == SeismicBase::compliant) {
    motion.input = s.choice("input", motion_input_names, std::optional(MotionInput::incident));
    motion.rock_density = s.number("rock_density", positive("kg/m³"));
    motion.rock_shear_wave_speed = s.number("rock_shear_wave_speed", positive("m/s"));
  } else {
    for (std::string_view key :
         {"input", "rock_density", "rock_shear_wave_speed", "rock_p_wave_speed"}) {
      s.reject(key, "only used with base = \"compliant\"");
    }
  }
  if (auto h = s.optional_table("horizontal", motion_component_keys)) {
    motion.horizontal = read_motion_component(*h, case_folder);
  }
  if (auto v = s.optional_table("vertical", motion_component_keys)) {
    motion.vertical = read_motion_component(*v, case_folder);
  }
  if (!motion.horizontal && !motion.vertical) {
    throw Error("{}: {}: neither [{}.horizontal] nor [{}.vertical]: no motion", s.where(), s.path(),
                s.path(), s.path());
  }
  if (motion.base == SeismicBase::compliant) {
    if (motion.vertical) {
      motion.rock_p_wave_speed =
          s.number("rock_p_wave_speed", Range{.min = motion.rock_shear_wave_speed,
                                              .unit = "m/s",
                                              .note = "above rock_shear_wave_speed"});
    } else {
      s.reject("rock_p_wave_speed", "only used with a vertical motion");
    }
  }
  // The boundaries the motion takes over must be given as the supports they replace.
  if (mesh.generator == MeshGenerator::gmsh) return motion;
  const auto require = [&](const std::string& side, BoundaryCondition condition,
                           std::string_view why) {
    const auto found = fem.failure_boundaries.find(side);
    if (found == fem.failure_boundaries.end() || found->second != condition) {
      s.fail(side == "base" ? "base" : "lateral",
             fmt::format("needs fem.failure.boundaries.{} = \"{}\" ({})", side,
                         to_string(condition), why));
    }
  };
  if (motion.base == SeismicBase::compliant) {
    require("base", BoundaryCondition::roller,
            "the vertical support of the compliant base before the shaking");
  }
  if (motion.lateral != LateralBoundary::boundaries) {
    for (const std::string side : {"left", "right"}) {
      require(side, BoundaryCondition::roller,
              "the support whose reaction the tied or viscous side keeps");
    }
  }
  return motion;
}

/// [[fem.recorders]].
std::vector<RecorderSpec> read_recorders(const Section& s) {
  std::vector<RecorderSpec> recorders;
  std::vector<std::string> taken;
  for (const Section& r :
       s.tables("recorders", Section::Keys{"name", "points", "node_set", "elements", "every"})) {
    RecorderSpec spec;
    spec.name = read_recorder_name(r, taken);
    taken.push_back(spec.name);
    const int kinds = int{r.has("points")} + int{r.has("node_set")} + int{r.has("elements")};
    if (kinds != 1) {
      throw Error("{}: {}: give exactly one of points, node_set, elements (found {})", r.where(),
                  r.path(), kinds);
    }
    if (r.has("points")) spec.points = read_points(r, "points");
    if (r.has("elements")) spec.elements = read_points(r, "elements");
    if (r.has("node_set")) spec.node_set = r.string("node_set");
    spec.every = r.number("every", non_negative("s"), 0.0);
    recorders.push_back(std::move(spec));
  }
  return recorders;
}

/// [fem.water] level: an elevation, or a table varying along x as points [[x, y], …].
void read_water_table(const Section& s, WaterSpec& water) {
  if (s.has("level") && s.node("level").is_array()) {
    const auto& items = s.reader().array(s.node("level"), s.dotted("level"));
    if (items.size() < 2) s.fail("level", "a water table profile needs at least 2 points [x, y]");
    for (std::size_t i = 0; i < items.size(); ++i) {
      const std::string item = fmt::format("{}[{}]", s.dotted("level"), i);
      const Vec2 p = s.reader().point(items[i], item);
      if (i > 0 && !(p.x() > water.profile.back().x())) {
        s.reader().fail(items[i], item, "x must increase strictly along the water table");
      }
      water.profile.push_back(p);
    }
    water.level = water.profile.front().y();
  } else {
    water.level = s.number("level", any_number());
  }
}

/// [fem.water]: the water table and the pore fluid (docs/method.md §10); `names` the node
/// sets a generated mesh has (empty: a Gmsh mesh, checked when the model is made).
WaterSpec read_water(const Section& s, const std::vector<std::string_view>& names) {
  WaterSpec water;
  read_water_table(s, water);
  water.density = s.number("density", positive("kg/m³"), water.density);
  water.bulk_modulus = s.number("bulk_modulus", positive("Pa"), water.bulk_modulus);
  water.tension_limit = s.number(
      "tension_limit", Range{.max = 0.0, .max_closed = true, .unit = "Pa"}, water.tension_limit);
  if (s.has("reservoir")) water.reservoir = s.number("reservoir", any_number());
  if (s.has("reservoir_extent")) {
    if (!water.reservoir) s.fail("reservoir_extent", "only used with a reservoir");
    const Vec2 extent = s.reader().point(s.node("reservoir_extent"), s.dotted("reservoir_extent"));
    if (!(extent.y() > extent.x()))
      s.fail("reservoir_extent", "expected [x_min, x_max], x_min < x_max");
    water.reservoir_x_min = extent.x();
    water.reservoir_x_max = extent.y();
  }
  if (s.has("drained")) {
    const auto& items = s.reader().array(s.node("drained"), s.dotted("drained"));
    for (std::size_t i = 0; i < items.size(); ++i) {
      const std::string dotted = fmt::format("{}[{}]", s.dotted("drained"), i);
      std::string name = s.reader().string(items[i], dotted);
      if (!names.empty() && std::ranges::find(names, name) == names.end()) {
        s.reader().inadmissible(items[i], dotted, fmt::format("\"{}\"", name),
                                fmt::format("a node set of the mesh: {}", join(names)));
      }
      water.drained.push_back(std::move(name));
    }
  }
  return water;
}

/// [fem.geostatic.boundaries] and, with a failure stage, [fem.failure.boundaries].
void read_stage_boundaries(const Section& s, const std::vector<std::string_view>& names,
                           FemSpec& fem) {
  const Section geostatic = s.table("geostatic", Section::Keys{"boundaries", "lateral"});
  const std::string lateral = geostatic.string("lateral", "boundaries");
  if (lateral != "boundaries" && lateral != "tied") {
    geostatic.fail("lateral", fmt::format("\"{}\" (expected \"boundaries\" or \"tied\")", lateral));
  }
  fem.geostatic_tied_sides = lateral == "tied";
  fem.geostatic_boundaries = read_boundaries(
      geostatic, "boundaries", names,
      "is not admissible in the geostatic stage (a linear static solve: free, roller or fixed)");
  if (fem.geostatic_tied_sides) {
    auto condition = [&](const char* side) {
      const auto at = fem.geostatic_boundaries.find(side);
      return at == fem.geostatic_boundaries.end() ? BoundaryCondition::free : at->second;
    };
    if (condition("left") != condition("right")) {
      geostatic.fail("lateral",
                     "\"tied\" needs the same geostatic boundary on the left and right edges");
    }
  }
  if (fem.failure_stage) {
    const Section failure = s.table("failure", Section::Keys{"boundaries"});
    fem.failure_boundaries = read_boundaries(failure, "boundaries", names, friction_problem(s));
  }
}

}  // namespace

FemSpec read_fem(const Section& root, const MeshSpec& mesh,
                 const std::filesystem::path& case_folder) {
  const Section s = root.table(
      "fem", Section::Keys{"failure_stage", "kinematics", "end_time", "checkpoint_times",
                           "checkpoint_every", "output_every", "vtk_every", "courant", "time_step",
                           "hourglass_coefficient", "friction_coefficient", "speed_limit_factor",
                           "damping", "geostatic", "failure", "motion", "recorders", "water"});
  FemSpec fem;
  fem.failure_stage = s.boolean("failure_stage", true);
  fem.kinematics =
      s.choice("kinematics", kinematics_names, std::optional(Kinematics::small_strain));
  if (fem.failure_stage) {
    fem.end_time = s.number("end_time", positive("s"));
  } else {
    for (std::string_view key : {"end_time", "checkpoint_times", "checkpoint_every", "failure"}) {
      s.reject(key, "only used when fem.failure_stage = true");
    }
  }
  read_schedule_and_step(s, fem);
  fem.hourglass_coefficient =
      s.number("hourglass_coefficient", non_negative(), fem.hourglass_coefficient);
  fem.friction_coefficient = s.number("friction_coefficient", non_negative(), 0.0);
  fem.speed_limit_factor = s.number("speed_limit_factor", positive(), fem.speed_limit_factor);
  if (auto damping = s.optional_table(
          "damping",
          Section::Keys{"rayleigh_mass", "rayleigh_stiffness", "ratio", "frequencies", "local"})) {
    fem.damping = read_damping(*damping);
  }

  // Generated and OpenSees meshes know left, right and base; Gmsh meshes name their own
  // boundaries (physical lines), checked against the mesh when it is read.
  const std::vector<std::string_view> names = mesh.generator == MeshGenerator::gmsh
                                                  ? std::vector<std::string_view>{}
                                                  : generated_mesh_boundaries;
  read_stage_boundaries(s, names, fem);
  if (auto motion = s.optional_table(
          "motion", Section::Keys{"start_time", "base", "lateral", "input", "rock_density",
                                  "rock_shear_wave_speed", "rock_p_wave_speed",
                                  "baseline_correction", "horizontal", "vertical"})) {
    if (!fem.failure_stage) motion->fail("start_time", "only used when fem.failure_stage = true");
    fem.motion = read_motion(*motion, case_folder, fem, mesh);
  }
  if (auto water = s.optional_table(
          "water", Section::Keys{"level", "density", "bulk_modulus", "tension_limit", "drained",
                                 "reservoir", "reservoir_extent"})) {
    fem.water = read_water(*water, names);
  }
  if (s.has("recorders")) {
    if (!fem.failure_stage) s.fail("recorders", "only used when fem.failure_stage = true");
    fem.recorders = read_recorders(s);
  }
  return fem;
}

}  // namespace slide::case_reader
