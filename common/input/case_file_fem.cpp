// The case reader's [fem] table: the stages, damping and boundaries of fem-solve.
// Section, the ranges and the shared readers are in case_file_reader.hpp.
#include <numbers>

#include "common/input/case_file_reader.hpp"

namespace slide::case_reader {

namespace {

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

}  // namespace

FemSpec read_fem(const Section& root, const MeshSpec& mesh) {
  const Section s =
      root.table("fem", Section::Keys{"failure_stage", "kinematics", "end_time", "checkpoint_times",
                                      "checkpoint_every", "output_every", "vtk_every", "courant",
                                      "time_step", "hourglass_coefficient", "friction_coefficient",
                                      "speed_limit_factor", "damping", "geostatic", "failure"});
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
  const Section geostatic = s.table("geostatic", Section::Keys{"boundaries"});
  fem.geostatic_boundaries = read_boundaries(
      geostatic, "boundaries", names,
      "is not admissible in the geostatic stage (a linear static solve: free, roller or fixed)");
  if (fem.failure_stage) {
    const Section failure = s.table("failure", Section::Keys{"boundaries"});
    fem.failure_boundaries = read_boundaries(failure, "boundaries", names, friction_problem(s));
  }
  return fem;
}

}  // namespace slide::case_reader

namespace slide {

RayleighCoefficients rayleigh_coefficients(const DampingRatio& ratio) {
  // ξ(ω) = α_M/(2ω) + β_K ω/2 = ξ at ω1 and ω2: two linear equations in α_M, β_K.
  const double omega1 = 2.0 * std::numbers::pi * ratio.frequencies[0];
  const double omega2 = 2.0 * std::numbers::pi * ratio.frequencies[1];
  return {.mass = 2.0 * ratio.ratio * omega1 * omega2 / (omega1 + omega2),
          .stiffness = 2.0 * ratio.ratio / (omega1 + omega2)};
}

}  // namespace slide
