// The case-file reader: the five cases of docs/method.md §7 load with the values docs/method.md
// gives, and broken case files are refused with a one-line message naming the file, the
// line and the dotted key at fault.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "common/base/error.hpp"
#include "common/input/case_file.hpp"

namespace slide {
namespace {

namespace fs = std::filesystem;

Case load_repository_case(std::string_view name) {
  return load_case(fs::path(SLIDE_SOURCE_DIR) / "cases" / name / "case.toml");
}

// ----------------------------------------------------------------------------- the five cases

// column-short as the programs receive it: what the reader fills in for the keys the
// file leaves out, and the quantities the file's comments derive from its values, each
// recomputed here from first principles (not read back from the file). A reader that
// dropped a key, applied another default or read an angle in the wrong unit fails here;
// so does an edit of the case that leaves its comments (Vs, f1, β_K, K0, τc) behind.
TEST(CaseFile, ColumnShortDerivedValuesAndDefaults) {
  const Case c = load_repository_case("column-short");
  ASSERT_EQ(c.materials.size(), 1u);
  const Material& soil = c.materials[0];

  // Unit: φ is in degrees. The left-out tension cut-off defaults to the Mohr–Coulomb apex
  // c·cot φ = 1000 Pa / tan(22.2°) = 2450 Pa (22.2 read as radians would give 4718 Pa).
  EXPECT_NEAR(soil.tension_cutoff, 1000.0 / std::tan(22.2 * std::numbers::pi / 180.0), 1e-9);
  EXPECT_NEAR(soil.tension_cutoff, 2450.4, 0.1);
  // K0 = ν/(1 − ν) = 0.30 (the file's comment), the geostatic stage's lateral ratio.
  EXPECT_NEAR(soil.k0(), 0.30, 0.005);

  // The damping comment: Vs = sqrt(G/ρ) = 75.4 m/s, f1 = Vs/(4 H0) = 0.471 Hz, and ξ = 5 %
  // between f1 and 5 f1 gives β_K = 0.005626 s (the value given) and α_M = 0.247 1/s
  // (left out, so zero); the ratio form itself was not used.
  const double shear_modulus = soil.youngs_modulus / (2.0 * (1.0 + soil.poisson_ratio));
  const double vs = std::sqrt(shear_modulus / soil.density);
  EXPECT_NEAR(vs, 75.4, 0.05);
  const double f1 = vs / (4.0 * c.metrics.initial_height);
  EXPECT_NEAR(f1, 0.471, 0.0005);
  const RayleighCoefficients five_percent =
      rayleigh_coefficients({.ratio = 0.05, .frequencies = {f1, 5.0 * f1}});
  EXPECT_NEAR(c.fem.damping.rayleigh_stiffness, five_percent.stiffness,
              1e-4 * five_percent.stiffness);
  EXPECT_NEAR(five_percent.mass, 0.247, 0.0005);
  EXPECT_EQ(c.fem.damping.rayleigh_mass, 0.0);
  EXPECT_EQ(c.fem.damping.local, 0.0);
  EXPECT_FALSE(c.fem.damping.ratio.has_value());

  // The main transfer at t_T = 2 s is τc = sqrt(H0/g) = 2.02 s to 1 %.
  const double tau_c = std::sqrt(c.metrics.initial_height / gravity_acceleration);
  EXPECT_NEAR(c.transfer.main_time / tau_c, 1.0, 0.01);

  // Defaults of the keys the file leaves out.
  EXPECT_EQ(c.fem.time_step, 0.0);  // Courant steps
  EXPECT_EQ(c.fem.hourglass_coefficient, 1.0);
  EXPECT_EQ(c.fem.speed_limit_factor, 5.0);
  EXPECT_TRUE(c.fem.checkpoint_times.empty());
  EXPECT_TRUE(c.fem.failure_stage);
  EXPECT_FALSE(c.transfer.rbf_polynomial.has_value());  // none for the global RBF
  EXPECT_EQ(c.transfer.rbf_shape, 0.0);                 // sqrt(A_box/N_g) at transfer
  EXPECT_EQ(c.mpm.pic_fraction, 0.0);
  EXPECT_EQ(c.mpm.time_step, 0.0);
  EXPECT_EQ(c.mpm.rest_threshold, 0.0);  // no rest stop: the MPM runs to 20 s
  EXPECT_EQ(c.mpm.rest_duration, 0.0);
  EXPECT_EQ(c.mpm.gravity_stage_duration, 0.0);
  EXPECT_EQ(c.metrics.foundation_level, 0.0);

  // The sections describe one column: the FE surface is the L0 × H0 cross-section of
  // [metrics] over the base y = 0, it lies inside the MPM grid, and every transfer time
  // lies within the FE run and before the MPM end time (the clock continues from t_T).
  ASSERT_EQ(c.mesh.surface.size(), 2u);
  EXPECT_EQ(c.mesh.surface.front(), Vec2(0.0, c.metrics.initial_height));
  EXPECT_EQ(c.mesh.surface.back(), Vec2(c.metrics.initial_length, c.metrics.initial_height));
  EXPECT_LE(c.mpm.domain_min.x(), 0.0);
  EXPECT_EQ(c.mpm.domain_min.y(), 0.0);  // the MPM base is the FE base
  EXPECT_GE(c.mpm.domain_max.x(), c.metrics.initial_length);
  EXPECT_GE(c.mpm.domain_max.y(), c.metrics.initial_height);
  ASSERT_FALSE(c.transfer.sweep_times.empty());
  EXPECT_TRUE(std::is_sorted(c.transfer.sweep_times.begin(), c.transfer.sweep_times.end()));
  EXPECT_GE(c.transfer.sweep_times.front(), 0.0);
  EXPECT_LE(c.transfer.sweep_times.back(), c.fem.end_time);
  EXPECT_LT(c.transfer.sweep_times.back(), c.mpm.end_time);
  EXPECT_NE(
      std::find(c.transfer.sweep_times.begin(), c.transfer.sweep_times.end(), c.transfer.main_time),
      c.transfer.sweep_times.end());
  EXPECT_EQ(c.material_index(c.mesh.material), 0);
  EXPECT_THROW(c.material_index("rock"), Error);
}

TEST(CaseFile, GeostaticLoads) {
  const Case c = load_repository_case("geostatic-4x4");
  EXPECT_EQ(c.materials[0].model, MaterialModel::linear_elastic);
  EXPECT_DOUBLE_EQ(c.materials[0].poisson_ratio, 0.23);
  EXPECT_DOUBLE_EQ(c.mesh.element_size, 0.25);
  EXPECT_FALSE(c.fem.failure_stage);
  EXPECT_TRUE(c.fem.failure_boundaries.empty());
  EXPECT_EQ(c.fem.geostatic_boundaries.size(), 3u);
  EXPECT_DOUBLE_EQ(c.transfer.main_time, 0.0);
  EXPECT_DOUBLE_EQ(c.mpm.cell_size, 0.25);
  EXPECT_EQ(c.mpm.initial_stress, InitialStress::k0);
  EXPECT_EQ(c.mpm.boundaries.at("base"), BoundaryCondition::roller);
  EXPECT_DOUBLE_EQ(c.metrics.initial_height, 4.0);
}

TEST(CaseFile, ColumnTallLoads) {
  const Case c = load_repository_case("column-tall");
  EXPECT_EQ(c.mesh.surface[1], Vec2(20.0, 80.0));
  EXPECT_DOUBLE_EQ(c.fem.end_time, 6.0);
  EXPECT_DOUBLE_EQ(c.transfer.main_time, 3.0);  // ≈ τc: the FE mesh lives to 3.7 s
  // APIC with cell smoothing runs every transfer at C = 0.5 (1 % PIC needed 0.45).
  EXPECT_DOUBLE_EQ(c.mpm.courant, 0.5);
  EXPECT_EQ(c.mpm.velocity_transfer, VelocityTransfer::apic);
  EXPECT_EQ(c.mpm.volumetric_smoothing, VolumetricSmoothing::cell);
  EXPECT_EQ(c.transfer.sweep_times.back(), 6.0);
  EXPECT_EQ(c.mpm.domain_max, Vec2(300.0, 85.0));
  EXPECT_DOUBLE_EQ(c.metrics.initial_length, 20.0);
  EXPECT_DOUBLE_EQ(c.metrics.initial_height, 80.0);
}

TEST(CaseFile, SlopeFrictionalLoads) {
  const Case c = load_repository_case("slope-frictional");
  EXPECT_DOUBLE_EQ(c.materials[0].friction_angle, 10.0);
  EXPECT_DOUBLE_EQ(c.materials[0].cohesion, 500.0);
  EXPECT_EQ(c.mesh.generator, MeshGenerator::blocks);
  ASSERT_EQ(c.mesh.blocks.size(), 4u);
  EXPECT_EQ(c.mesh.blocks[0].cells_u, 20);
  // The three blocks under the face meet at the triangle's centroid.
  const Vec2 centroid(80.0 / 3.0, 20.0 / 3.0);
  EXPECT_NEAR((c.mesh.blocks[1].corners[2] - centroid).norm(), 0.0, 1e-12);
  EXPECT_NEAR((c.mesh.blocks[2].corners[3] - centroid).norm(), 0.0, 1e-12);
  EXPECT_NEAR((c.mesh.blocks[3].corners[1] - centroid).norm(), 0.0, 1e-12);
  EXPECT_NEAR(c.fem.friction_coefficient, std::tan(10.0 * std::numbers::pi / 180.0), 1e-4);
  EXPECT_EQ(c.fem.failure_boundaries.at("right"), BoundaryCondition::free);
  EXPECT_DOUBLE_EQ(c.mpm.local_damping, 0.01);
  EXPECT_DOUBLE_EQ(c.mpm.end_time, 30.0);
  EXPECT_DOUBLE_EQ(c.metrics.initial_length, 40.0);
  EXPECT_DOUBLE_EQ(c.metrics.initial_height, 20.0);
}

TEST(CaseFile, SlopeCohesiveLoads) {
  const Case c = load_repository_case("slope-cohesive");
  EXPECT_DOUBLE_EQ(c.materials[0].density, 1690.0);
  EXPECT_DOUBLE_EQ(c.materials[0].friction_angle, 3.6);
  EXPECT_DOUBLE_EQ(c.materials[0].cohesion, 5800.0);
  ASSERT_EQ(c.mesh.surface.size(), 4u);
  EXPECT_EQ(c.mesh.surface[2], Vec2(50.0, 5.0));
  EXPECT_EQ(c.mesh.surface[3], Vec2(160.0, 5.0));
  EXPECT_EQ(c.fem.failure_boundaries.at("right"), BoundaryCondition::roller);
  EXPECT_NEAR(c.mpm.friction_coefficient, std::tan(3.6 * std::numbers::pi / 180.0), 1e-4);
  EXPECT_EQ(c.mpm.boundaries.at("right"), BoundaryCondition::roller);
  EXPECT_EQ(c.transfer.sweep_times.size(), 12u);
  EXPECT_DOUBLE_EQ(c.metrics.initial_length, 50.0);
  EXPECT_DOUBLE_EQ(c.metrics.initial_height, 10.0);
}

// ----------------------------------------------------------------------------- a small valid case

const std::string profile_mesh = R"([mesh]
generator = "profile"
element_size = 1.0
surface = [[0.0, 4.0], [4.0, 4.0]]
material = "soil"
)";

const std::string blocks_mesh = R"([mesh]
generator = "blocks"

[[mesh.blocks]]
corners = [[0.0, 0.0], [2.0, 0.0], [2.0, 4.0], [0.0, 4.0]]
cells = [2, 4]
material = "soil"

[[mesh.blocks]]
corners = [[2.0, 0.0], [4.0, 0.0], [4.0, 2.0], [2.0, 2.0]]
cells = [2, 2]
material = "soil"

[[mesh.blocks]]
corners = [[2.0, 2.0], [4.0, 2.0], [4.0, 4.0], [2.0, 4.0]]
cells = [2, 2]
material = "soil"
)";

std::string small_case(const std::string& mesh = profile_mesh) {
  return R"([case]
name = "unit-test"

[[materials]]
name = "soil"
model = "mohr-coulomb"
density = 1700.0
youngs_modulus = 23.8e6
poisson_ratio = 0.23
friction_angle = 22.2
cohesion = 1000.0
dilation_angle = 0.0

)" + mesh +
         R"(
[fem]
end_time = 2.0
checkpoint_every = 1.0
friction_coefficient = 0.5

[fem.geostatic.boundaries]
left = "roller"
right = "roller"
base = "roller"

[fem.failure.boundaries]
left = "roller"
right = "free"
base = "friction"

[transfer]
particles_per_element = [4, 4]
sweep_times = [0.0, 1.0, 2.0]
main_time = 1.0

[mpm]
domain = [[0.0, 0.0], [20.0, 5.0]]
cell_size = 1.0
end_time = 5.0
friction_coefficient = 0.5

[mpm.boundaries]
left = "roller"
right = "roller"
base = "friction"

[metrics]
initial_length = 4.0
initial_height = 4.0
)";
}

/// The small case with `lines` added to its [mpm] table (after cell_size).
std::string small_case_with_mpm_lines(const std::string& lines) {
  std::string text = small_case();
  const std::string at = "cell_size = 1.0\n";
  text.replace(text.find(at), at.size(), at + lines);
  return text;
}

TEST(CaseFile, SmallCaseLoadsWithDefaults) {
  const Case c = parse_case(small_case(), "case.toml");
  EXPECT_EQ(c.file, fs::path("case.toml"));
  EXPECT_EQ(c.fem.kinematics, Kinematics::small_strain);
  EXPECT_DOUBLE_EQ(c.fem.courant, 0.5);
  EXPECT_DOUBLE_EQ(c.fem.hourglass_coefficient, 1.0);
  EXPECT_EQ(c.transfer.particles_triangle, 16);
  EXPECT_EQ(c.transfer.stress_interpolation, StressInterpolation::rbf);
  EXPECT_FALSE(c.transfer.rbf_polynomial.has_value());
  EXPECT_EQ(c.mpm.shape_function, ShapeFunction::gimp);
  EXPECT_EQ(c.mpm.update_scheme, UpdateScheme::musl);
  EXPECT_EQ(c.mpm.velocity_transfer, VelocityTransfer::flip_pic);
  EXPECT_EQ(c.mpm.pic_fraction, 0.0);
  EXPECT_EQ(c.mpm.particle_exit, ParticleExit::freeze);
  EXPECT_EQ(c.mpm.boundaries.count("top"), 0u);  // unlisted boundaries are free
  EXPECT_DOUBLE_EQ(c.metrics.bin_width, 2.0);
  EXPECT_DOUBLE_EQ(c.metrics.profile_percentile, 99.0);
}

TEST(CaseFile, BlocksWithMatchingEdgesLoad) {
  const Case c = parse_case(small_case(blocks_mesh), "case.toml");
  ASSERT_EQ(c.mesh.blocks.size(), 3u);
  EXPECT_EQ(c.mesh.blocks[2].corners[2], Vec2(4.0, 4.0));
  EXPECT_EQ(c.mesh.blocks[0].cells_v, 4);
}

TEST(CaseFile, ParticleCountMayBeOneInteger) {
  std::string text = small_case();
  text.replace(text.find("particles_per_element = [4, 4]"), 30, "particles_per_element = 3");
  const Case c = parse_case(text, "case.toml");
  EXPECT_EQ(c.transfer.particles_x, 3);
  EXPECT_EQ(c.transfer.particles_y, 3);
}

TEST(CaseFile, TensionCutoffDefaultsToTheApexAndIsInfiniteWithoutFriction) {
  std::string text = small_case();
  text.replace(text.find("friction_angle = 22.2"), 21, "friction_angle = 0.0");
  const Case c = parse_case(text, "case.toml");
  EXPECT_EQ(c.materials[0].tension_cutoff, std::numeric_limits<double>::infinity());
  text.replace(text.find("dilation_angle = 0.0"), 20, "tension_cutoff = 250.0");
  EXPECT_DOUBLE_EQ(parse_case(text, "case.toml").materials[0].tension_cutoff, 250.0);
}

// Issue 13: a case file that never ends (/dev/zero) was read to 4.2 GB before failing.
// One byte over the cap is refused at once, naming the file; the cap itself is read.
TEST(CaseFile, AFileLargerThanTheCapIsRefusedWithoutReadingIt) {
  try {
    load_case("/dev/zero");
    FAIL() << "/dev/zero was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/zero: larger than 4 MiB, not a case file");
  }
  const std::filesystem::path big =
      std::filesystem::path(SLIDE_BINARY_DIR) / "tests" / "common" / "big_case.toml";
  std::filesystem::create_directories(big.parent_path());
  std::ofstream(big) << std::string(max_case_file_bytes, '#');  // comments only: in the cap
  try {
    load_case(big);
    FAIL() << "a file of comments was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find("larger than"), std::string::npos) << e.what();
  }
}

TEST(CaseFile, GmshFileIsFoundRelativeToTheCaseFolder) {
  const fs::path folder = fs::temp_directory_path() / "slide-test-case-file-gmsh";
  fs::create_directories(folder);
  std::ofstream(folder / "slope.msh") << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  const std::string mesh =
      "[mesh]\ngenerator = \"gmsh\"\nelement = \"tri3\"\nfile = \"slope.msh\"\n";
  std::string text = small_case(mesh);
  // Gmsh meshes name their own boundaries (physical lines).
  text.replace(text.find("right = \"free\""), 14, "toe_face = \"free\"");
  const Case c = parse_case(text, folder / "case.toml");
  EXPECT_EQ(c.mesh.generator, MeshGenerator::gmsh);
  EXPECT_EQ(c.mesh.element_type, ElementType::tri3);
  EXPECT_TRUE(c.mesh.gmsh_file.is_absolute());
  EXPECT_TRUE(fs::equivalent(c.mesh.gmsh_file, folder / "slope.msh"));
  EXPECT_EQ(c.fem.failure_boundaries.at("toe_face"), BoundaryCondition::free);
  fs::remove_all(folder);
}

TEST(CaseFile, NameMustMatchTheFolderUnderCases) {
  const std::string text = small_case();
  EXPECT_NO_THROW(parse_case(text, "/somewhere/cases/unit-test/case.toml"));
  try {
    parse_case(text, "/somewhere/cases/other-name/case.toml");
    FAIL() << "a case named unlike its folder was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("case.name"), std::string::npos) << error.what();
  }
}

TEST(CaseFile, MissingFileIsAnError) {
  EXPECT_THROW(load_case("/nonexistent/cases/none/case.toml"), Error);
}

TEST(CaseFile, EnumNamesAreTheCaseFileSpellings) {
  EXPECT_EQ(to_string(Kinematics::updated_lagrangian), "updated-lagrangian");
  EXPECT_EQ(to_string(StressInterpolation::rbf_local), "rbf-local");
  EXPECT_EQ(to_string(RbfPolynomial::linear), "linear");
  EXPECT_EQ(to_string(ShapeFunction::gimp), "gimp");
  EXPECT_EQ(to_string(UpdateScheme::usl), "usl");
  EXPECT_EQ(to_string(VelocityTransfer::flip_pic), "flip-pic");
  EXPECT_EQ(to_string(VelocityTransfer::apic), "apic");
}

// mpm.velocity_transfer: "flip-pic" (the default, with pic_fraction) or "apic". With apic
// a pic_fraction is read (and checked) but ignored: the tuning key of the option not
// selected, as the reader's policy has it, so that a case switches with one line.
TEST(CaseFile, VelocityTransferIsFlipPicOrApicAndApicIgnoresThePicFraction) {
  auto with = [](const std::string& lines) {
    return parse_case(small_case_with_mpm_lines(lines), "case.toml");
  };
  const Case flip = with("pic_fraction = 0.01\n");
  EXPECT_EQ(flip.mpm.velocity_transfer, VelocityTransfer::flip_pic);
  EXPECT_EQ(flip.mpm.pic_fraction, 0.01);
  const Case apic = with("velocity_transfer = \"apic\"\n");
  EXPECT_EQ(apic.mpm.velocity_transfer, VelocityTransfer::apic);
  const Case apic_with_share = with("velocity_transfer = \"apic\"\npic_fraction = 0.01\n");
  EXPECT_EQ(apic_with_share.mpm.velocity_transfer, VelocityTransfer::apic);
  EXPECT_EQ(apic_with_share.mpm.pic_fraction, 0.01);  // kept for the record, not used
  EXPECT_THROW(with("velocity_transfer = \"apic\"\npic_fraction = 1.5\n"), Error);
  try {
    with("velocity_transfer = \"xpic\"\n");
    FAIL() << "an unknown velocity transfer was accepted";
  } catch (const Error& error) {
    // case.toml:<line>: mpm.velocity_transfer = "xpic" is not admissible (expected one of:
    // flip-pic, apic)
    const std::string message = error.what();
    EXPECT_NE(message.find("mpm.velocity_transfer"), std::string::npos) << message;
    EXPECT_NE(message.find("\"xpic\""), std::string::npos) << message;
    EXPECT_NE(message.find("flip-pic, apic"), std::string::npos) << message;
  }
}

// mpm.volumetric_smoothing: "none" or "cell"; absent, "cell" when some material is
// plastic in the MPM phase (the small case's Mohr–Coulomb soil), "none" when all are
// elastic there (mpm_model = "linear-elastic").
TEST(CaseFile, VolumetricSmoothingIsCellForPlasticMaterialsUnlessTheCaseSaysOtherwise) {
  auto with = [](const std::string& lines, const std::string& mpm_model = "mohr-coulomb") {
    std::string text = small_case_with_mpm_lines(lines);
    const std::string model = "model = \"mohr-coulomb\"\n";
    text.replace(text.find(model), model.size(), model + "mpm_model = \"" + mpm_model + "\"\n");
    return parse_case(text, "case.toml");
  };
  EXPECT_EQ(with("").mpm.volumetric_smoothing, VolumetricSmoothing::cell);
  EXPECT_EQ(with("", "linear-elastic").mpm.volumetric_smoothing, VolumetricSmoothing::none);
  EXPECT_EQ(with("volumetric_smoothing = \"none\"\n").mpm.volumetric_smoothing,
            VolumetricSmoothing::none);
  EXPECT_EQ(with("volumetric_smoothing = \"cell\"\n", "linear-elastic").mpm.volumetric_smoothing,
            VolumetricSmoothing::cell);
  EXPECT_EQ(to_string(VolumetricSmoothing::cell), "cell");
  try {
    with("volumetric_smoothing = \"node\"\n");
    FAIL() << "an unknown smoothing was accepted";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("mpm.volumetric_smoothing"), std::string::npos) << message;
    EXPECT_NE(message.find("none, cell"), std::string::npos) << message;
  }
}

// ----------------------------------------------------------------------------- broken files

/// One broken case file: `find` (first occurrence) in the small case is replaced by
/// `replace` (empty `find`: `replace` is appended). The error must name `key` and, when
/// `line_of` is given, the line of the first occurrence of `line_of` in the broken text.
struct Broken {
  std::string_view label;
  std::string_view find;
  std::string_view replace;
  std::string_view key;
  std::string_view line_of;
  bool blocks = false;  ///< edit the blocks variant of the small case
};

const Broken broken_cases[] = {
    {"unknown table", "", "[extra]\nx = 1\n", "extra: unknown key", "[extra]"},
    {"misspelt key", "density = 1700.0", "densty = 1700.0", "materials[0].densty: unknown key",
     "densty"},
    {"unknown key in a nested table", "checkpoint_every = 1.0", "checkpoint_evry = 1.0",
     "fem.checkpoint_evry: unknown key", "checkpoint_evry"},
    {"missing required key", "generator = \"profile\"\n", "",
     "mesh.generator: missing required key", "[mesh]"},
    {"missing required table", "[metrics]\ninitial_length = 4.0\ninitial_height = 4.0\n", "",
     "metrics: missing required table", ""},
    {"string for a number", "end_time = 2.0", "end_time = \"2\"", "fem.end_time: expected a number",
     "end_time = \"2\""},
    {"string for a boolean", "[fem]\n", "[fem]\nfailure_stage = \"no\"\n", "fem.failure_stage",
     "failure_stage"},
    {"float for an integer", "particles_per_element = [4, 4]", "particles_per_element = [4.0, 4]",
     "transfer.particles_per_element[0]: expected an integer", "particles_per_element"},
    {"negative density", "density = 1700.0", "density = -1700.0",
     "materials[0].density = -1700 is not admissible", "density ="},
    {"incompressible", "poisson_ratio = 0.23", "poisson_ratio = 0.5", "materials[0].poisson_ratio",
     "poisson_ratio"},
    {"friction angle 90", "friction_angle = 22.2", "friction_angle = 90.0",
     "materials[0].friction_angle", "friction_angle"},
    {"dilation above friction", "dilation_angle = 0.0", "dilation_angle = 30.0",
     "materials[0].dilation_angle", "dilation_angle"},
    {"unknown model", "\"mohr-coulomb\"", "\"drucker-prager\"", "materials[0].model",
     "drucker-prager"},
    {"strength on an elastic material", "\"mohr-coulomb\"", "\"linear-elastic\"",
     "materials[0].friction_angle", "friction_angle"},
    {"materials as one table", "[[materials]]", "[materials]", "materials", ""},
    {"duplicate material name", "",
     "[[materials]]\nname = \"soil\"\nmodel = \"linear-elastic\"\ndensity = 1.0\n"
     "youngs_modulus = 1.0\npoisson_ratio = 0.2\n",
     "materials[1].name", "name = \"soil\"\nmodel = \"linear"},
    {"unknown element", "generator = \"profile\"", "generator = \"profile\"\nelement = \"quad8\"",
     "mesh.element", "quad8"},
    {"unknown generator", "generator = \"profile\"", "generator = \"triangle\"", "mesh.generator",
     "triangle"},
    {"unknown material in the mesh", "material = \"soil\"", "material = \"rock\"", "mesh.material",
     "rock"},
    {"surface x not increasing", "[[0.0, 4.0], [4.0, 4.0]]", "[[0.0, 4.0], [4.0, 4.0], [3.0, 2.0]]",
     "mesh.surface[2]", "surface ="},
    {"surface away from the wall", "[[0.0, 4.0], [4.0, 4.0]]", "[[1.0, 4.0], [4.0, 4.0]]",
     "mesh.surface[0]", "surface ="},
    {"surface below the base", "[[0.0, 4.0], [4.0, 4.0]]", "[[0.0, 4.0], [4.0, 0.0]]",
     "mesh.surface[1]", "surface ="},
    {"geometry of another generator", "element_size = 1.0", "element_size = 1.0\nfile = \"x.msh\"",
     "mesh.file: not used by generator", "file ="},
    {"block corners clockwise", "[[0.0, 0.0], [2.0, 0.0], [2.0, 4.0], [0.0, 4.0]]",
     "[[0.0, 0.0], [0.0, 4.0], [2.0, 4.0], [2.0, 0.0]]", "mesh.blocks[0].corners",
     "corners =", true},
    {"block edges with hanging nodes", "cells = [2, 4]", "cells = [2, 3]", "mesh.blocks[1].cells",
     "", true},
    {"profile key in a blocks mesh", "generator = \"blocks\"",
     "generator = \"blocks\"\nelement_size = 1.0", "mesh.element_size", "element_size", true},
    {"courant 0", "end_time = 2.0", "end_time = 2.0\ncourant = 0.0", "fem.courant", "courant"},
    {"checkpoint after the end", "checkpoint_every = 1.0", "checkpoint_times = [1.0, 3.0]",
     "fem.checkpoint_times[1]", "checkpoint_times"},
    {"failure settings without a failure stage", "[fem]\n", "[fem]\nfailure_stage = false\n",
     "fem.end_time: only used when fem.failure_stage = true", "end_time = 2.0"},
    {"unknown boundary name", "right = \"free\"", "rigth = \"free\"",
     "fem.failure.boundaries.rigth: unknown key", "rigth"},
    {"unknown boundary condition", "right = \"free\"", "right = \"loose\"",
     "fem.failure.boundaries.right", "loose"},
    {"friction without coefficient", "friction_coefficient = 0.5\n", "",
     "fem.failure.boundaries.base", "base = \"friction\""},
    {"friction in the geostatic stage", "base = \"roller\"", "base = \"friction\"",
     "fem.geostatic.boundaries.base", "base = \"friction\""},
    {"too many particles", "particles_per_element = [4, 4]", "particles_per_element = [33, 4]",
     "transfer.particles_per_element[0]", "particles_per_element"},
    {"no such triangle rule", "[transfer]\n", "[transfer]\nparticles_per_triangle = 5\n",
     "transfer.particles_per_triangle", "particles_per_triangle"},
    {"unknown interpolation", "[transfer]\n", "[transfer]\nstress_interpolation = \"kriging\"\n",
     "transfer.stress_interpolation", "kriging"},
    {"sweep beyond the FE run", "sweep_times = [0.0, 1.0, 2.0]", "sweep_times = [0.0, 1.0, 3.0]",
     "transfer.sweep_times[2]", "sweep_times"},
    {"sweep not increasing", "sweep_times = [0.0, 1.0, 2.0]", "sweep_times = [0.0, 2.0, 1.0]",
     "transfer.sweep_times[2]", "sweep_times"},
    {"cell size not dividing the domain", "cell_size = 1.0", "cell_size = 0.3", "mpm.cell_size",
     "cell_size"},
    {"domain upside down", "[[0.0, 0.0], [20.0, 5.0]]", "[[0.0, 5.0], [20.0, 0.0]]", "mpm.domain",
     "domain ="},
    {"domain not containing the body", "[[0.0, 0.0], [20.0, 5.0]]", "[[0.0, 0.0], [20.0, 3.0]]",
     "mpm.domain", "domain ="},
    {"unknown velocity transfer", "cell_size = 1.0",
     "cell_size = 1.0\nvelocity_transfer = \"flip\"", "mpm.velocity_transfer", "velocity_transfer"},
    {"pic fraction 2", "cell_size = 1.0", "cell_size = 1.0\npic_fraction = 2.0", "mpm.pic_fraction",
     "pic_fraction"},
    {"local damping 1", "cell_size = 1.0", "cell_size = 1.0\nlocal_damping = 1.0",
     "mpm.local_damping", "local_damping"},
    {"negative stiffness damping", "[fem.geostatic.boundaries]",
     "[fem.damping]\nrayleigh_stiffness = -0.01\n\n[fem.geostatic.boundaries]",
     "fem.damping.rayleigh_stiffness = -0.01 is not admissible", "rayleigh_stiffness"},
    {"damping ratio 1", "[fem.geostatic.boundaries]",
     "[fem.damping]\nratio = 1.0\nfrequencies = [1.0, 10.0]\n\n[fem.geostatic.boundaries]",
     "fem.damping.ratio = 1 is not admissible", "ratio = 1.0"},
    {"damping ratio without frequencies", "[fem.geostatic.boundaries]",
     "[fem.damping]\nratio = 0.05\n\n[fem.geostatic.boundaries]",
     "fem.damping.frequencies: missing required key", "[fem.damping]"},
    {"damping frequencies without ratio", "[fem.geostatic.boundaries]",
     "[fem.damping]\nfrequencies = [1.0, 10.0]\n\n[fem.geostatic.boundaries]",
     "fem.damping.frequencies: only used with fem.damping.ratio", "frequencies"},
    {"one damping frequency", "[fem.geostatic.boundaries]",
     "[fem.damping]\nratio = 0.05\nfrequencies = [1.0]\n\n[fem.geostatic.boundaries]",
     "fem.damping.frequencies: expected [f1, f2]", "frequencies"},
    {"damping frequencies not increasing", "[fem.geostatic.boundaries]",
     "[fem.damping]\nratio = 0.05\nfrequencies = [10.0, 1.0]\n\n[fem.geostatic.boundaries]",
     "fem.damping.frequencies[1]", "frequencies"},
    {"damping frequency zero", "[fem.geostatic.boundaries]",
     "[fem.damping]\nratio = 0.05\nfrequencies = [0.0, 1.0]\n\n[fem.geostatic.boundaries]",
     "fem.damping.frequencies[0] = 0 is not admissible", "frequencies"},
    {"MPM ends before the transfer", "end_time = 5.0", "end_time = 1.5", "mpm.end_time",
     "end_time = 1.5"},
    {"grid boundary name", "base = \"friction\"\n\n[metrics]", "bottom = \"friction\"\n\n[metrics]",
     "mpm.boundaries.bottom: unknown key", "bottom"},
    {"gravity stage without duration", "cell_size = 1.0",
     "cell_size = 1.0\ninitial_stress = \"gravity\"",
     "mpm.gravity_stage_duration: missing required key", "[mpm]"},
    {"missing metric", "initial_height = 4.0\n", "", "metrics.initial_height: missing required key",
     "[metrics]"},
    {"percentile above 100", "initial_height = 4.0",
     "initial_height = 4.0\nprofile_percentile = 101", "metrics.profile_percentile",
     "profile_percentile"},
    {"badly formed case name", "name = \"unit-test\"", "name = \"Unit Test\"", "case.name",
     "Unit Test"},
    {"TOML syntax error", "density = 1700.0", "density = = 1700.0", "TOML syntax error",
     "density = ="},
    {"TOML duplicate key", "density = 1700.0", "density = 1700.0\ndensity = 1800.0",
     "TOML syntax error", "density = 1800.0"},
};

int line_of(const std::string& text, std::string_view needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

class CaseFileBroken : public testing::TestWithParam<Broken> {};

TEST_P(CaseFileBroken, IsRefusedWithKeyAndLine) {
  const Broken& broken = GetParam();
  std::string text = broken.blocks ? small_case(blocks_mesh) : small_case();
  if (broken.find.empty()) {
    text += "\n";
    text += broken.replace;
  } else {
    const auto at = text.find(broken.find);
    ASSERT_NE(at, std::string::npos) << "the edit does not apply: " << broken.find;
    text.replace(at, broken.find.size(), broken.replace);
  }
  try {
    parse_case(text, "case.toml");
    FAIL() << broken.label << ": accepted";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_TRUE(message.starts_with("case.toml")) << message;
    EXPECT_NE(message.find(broken.key), std::string::npos) << message;
    if (!broken.line_of.empty()) {
      const int line = line_of(text, broken.line_of);
      ASSERT_GT(line, 0) << "no such text: " << broken.line_of;
      EXPECT_TRUE(message.starts_with(fmt::format("case.toml:{}: ", line)))
          << message << " (expected line " << line << ")";
    }
  }
}

std::string test_name(const testing::TestParamInfo<Broken>& info) {
  std::string name;
  for (char ch : info.param.label) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(CaseFile, CaseFileBroken, testing::ValuesIn(broken_cases), test_name);

// ----------------------------------------------------------------------------- damping

/// The small case with a [fem.damping] table of `keys` (one "key = value" a line).
std::string with_damping(std::string_view keys) {
  std::string text = small_case();
  const std::string anchor = "[fem.geostatic.boundaries]";
  text.replace(text.find(anchor), anchor.size(),
               fmt::format("[fem.damping]\n{}\n{}", keys, anchor));
  return text;
}

TEST(CaseFile, RayleighDampingIsGivenAsCoefficientsOrAsARatioAtTwoFrequencies) {
  const DampingSpec none = parse_case(small_case(), "case.toml").fem.damping;
  EXPECT_EQ(none.rayleigh_mass, 0.0);
  EXPECT_EQ(none.rayleigh_stiffness, 0.0);
  EXPECT_EQ(none.local, 0.0);
  EXPECT_FALSE(none.ratio.has_value());

  const DampingSpec coefficients =
      parse_case(with_damping("rayleigh_mass = 0.5\nrayleigh_stiffness = 0.002\nlocal = 0.1\n"),
                 "case.toml")
          .fem.damping;
  EXPECT_DOUBLE_EQ(coefficients.rayleigh_mass, 0.5);
  EXPECT_DOUBLE_EQ(coefficients.rayleigh_stiffness, 0.002);
  EXPECT_DOUBLE_EQ(coefficients.local, 0.1);
  EXPECT_FALSE(coefficients.ratio.has_value());

  // ξ = 0.05 at 1 and 10 Hz: α_M = 2ξ ω1 ω2/(ω1 + ω2), β_K = 2ξ/(ω1 + ω2), and the
  // Rayleigh ratio ξ(ω) = α_M/(2ω) + β_K ω/2 is ξ at both frequencies.
  const DampingSpec ratio =
      parse_case(with_damping("ratio = 0.05\nfrequencies = [1.0, 10.0]\n"), "case.toml")
          .fem.damping;
  const double omega1 = 2.0 * std::numbers::pi, omega2 = 20.0 * std::numbers::pi;
  EXPECT_NEAR(ratio.rayleigh_mass, 0.1 * omega1 * omega2 / (omega1 + omega2), 1e-14);
  EXPECT_NEAR(ratio.rayleigh_stiffness, 0.1 / (omega1 + omega2), 1e-17);
  for (const double omega : {omega1, omega2}) {
    EXPECT_NEAR(ratio.rayleigh_mass / (2.0 * omega) + ratio.rayleigh_stiffness * omega / 2.0, 0.05,
                1e-15);
  }
  ASSERT_TRUE(ratio.ratio.has_value());
  EXPECT_DOUBLE_EQ(ratio.ratio->ratio, 0.05);
  EXPECT_EQ(ratio.ratio->frequencies, (std::array<double, 2>{1.0, 10.0}));
  EXPECT_EQ(ratio.local, 0.0);
}

TEST(CaseFile, BothFormsOfRayleighDampingAreAOneLineErrorNamingTheKeys) {
  for (const std::string_view key : {"rayleigh_mass", "rayleigh_stiffness"}) {
    const std::string text =
        with_damping(fmt::format("ratio = 0.05\nfrequencies = [1.0, 10.0]\n{} = 0.1\n", key));
    try {
      parse_case(text, "case.toml");
      FAIL() << "ratio with " << key << " was accepted";
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_TRUE(message.starts_with(fmt::format("case.toml:{}: ", line_of(text, key))))
          << message;
      EXPECT_NE(message.find("fem.damping.ratio"), std::string::npos) << message;
      EXPECT_NE(message.find(fmt::format("fem.damping.{}", key)), std::string::npos) << message;
    }
  }
}

// ----------------------------------------------------------------------------- PM4Sand

namespace pm4sand_case {

/// The small case with its soil turned into a PM4Sand sand: `table` is the body of
/// [materials.pm4sand]; `material_lines` are added to the material.
std::string text(std::string_view table, std::string_view material_lines = "") {
  std::string text = small_case();
  // The soil's model and Mohr–Coulomb parameters give way to the sand's.
  const auto from = text.find("model = \"mohr-coulomb\"");
  const std::string last = "dilation_angle = 0.0\n";
  const auto to = text.find(last, from) + last.size();
  const std::string sand =
      fmt::format("model = \"pm4sand\"\ndensity = 1950.0\n{}\n[materials.pm4sand]\n{}\n",
                  material_lines, table);
  text.replace(from, to - from, sand);
  return text;
}

}  // namespace pm4sand_case

TEST(CaseFile, Pm4SandTakesItsParametersAndDerivesTheElasticStage) {
  const Case c = parse_case(pm4sand_case::text("relative_density = 0.55\ncontraction_rate = 0.45\n"
                                               "c_z = 300.0\n"),
                            "case.toml");
  const Material& m = c.materials.at(0);
  EXPECT_EQ(m.model, MaterialModel::pm4sand);
  EXPECT_EQ(m.pm4sand.relative_density, 0.55);
  EXPECT_EQ(m.pm4sand.contraction_rate, 0.45);
  EXPECT_EQ(m.pm4sand.c_z, 300.0);
  EXPECT_TRUE(std::isnan(m.pm4sand.shear_modulus_coefficient));  // derived from D_R
  EXPECT_EQ(m.poisson_ratio, 0.3);
  const double g0 = 167.0 * std::sqrt(46.0 * 0.55 * 0.55 + 2.5);
  EXPECT_DOUBLE_EQ(m.youngs_modulus, 2.0 * 1.3 * g0 * 101.3e3);
}

TEST(CaseFile, Pm4SandTakesBlowCountAndShearWaveSpeedInsteadOfDrAndG0) {
  const Case c = parse_case(
      pm4sand_case::text("blow_count = 7.36\nshear_wave_speed = 160.0\ncontraction_rate = 0.5\n"),
      "case.toml");
  const Pm4SandParameters& p = c.materials.at(0).pm4sand;
  EXPECT_DOUBLE_EQ(p.relative_density, std::sqrt(7.36 / 46.0));  // 0.40
  EXPECT_DOUBLE_EQ(p.shear_modulus_coefficient, 1950.0 * 160.0 * 160.0 / 101.3e3);
  EXPECT_THROW(parse_case(pm4sand_case::text("blow_count = 7.36\nrelative_density = 0.4\n"
                                             "contraction_rate = 0.5\n"),
                          "case.toml"),
               Error);
}

TEST(CaseFile, Pm4SandCalibratesItsContractionRateToTheCrr) {
  const Case c = parse_case(
      pm4sand_case::text("relative_density = 0.55\ncalibrate_to_crr = true\n"), "case.toml");
  const Pm4SandParameters& p = c.materials.at(0).pm4sand;
  // The Idriss–Boulanger CRR at (N1)60cs = 46 × 0.55² (METHOD §10: 0.147).
  EXPECT_NEAR(p.calibrated_crr, 0.147, 5e-4);
  EXPECT_NEAR(p.calibrated_cycles, 15.0, 0.15);
  EXPECT_GT(p.contraction_rate, 0.1);
  EXPECT_LT(p.contraction_rate, 2.0);
}

TEST(CaseFile, Pm4SandMistakesAreOneLineErrorsNamingTheKey) {
  const std::array<std::pair<std::string, std::string_view>, 6> broken{{
      {pm4sand_case::text("relative_density = 0.5\ncontraction_rate = 0.5\n",
                          "youngs_modulus = 1e8"),
       "youngs_modulus: not used with model \"pm4sand\""},
      {pm4sand_case::text("relative_density = 0.5\n"), "give either contraction_rate"},
      {pm4sand_case::text(
           "relative_density = 0.5\ncontraction_rate = 0.5\ncalibrate_to_crr = true\n"),
       "give either contraction_rate"},
      {pm4sand_case::text("relative_density = 0.5\ncontraction_rate = 0.5\nhpo = 1\n"),
       "materials[0].pm4sand.hpo: unknown key"},
      {pm4sand_case::text("relative_density = 2.0\ncontraction_rate = 0.5\n"),
       "pm4sand.relative_density = 2 is not admissible"},
      {pm4sand_case::text("relative_density = 0.5\ncontraction_rate = 0.5\ntarget_crr = 0.2\n"),
       "target_crr: only used with calibrate_to_crr"},
  }};
  for (const auto& [text, fragment] : broken) {
    try {
      parse_case(text, "case.toml");
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_TRUE(message.starts_with("case.toml:")) << message;
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
    }
  }
  // A pm4sand table on another model.
  std::string text = small_case();
  text.replace(text.find("dilation_angle = 0.0\n"), 21,
               "dilation_angle = 0.0\n\n[materials.pm4sand]\nrelative_density = 0.5\n");
  EXPECT_THROW(
      {
        try {
          parse_case(text, "case.toml");
        } catch (const Error& error) {
          EXPECT_NE(std::string(error.what()).find("pm4sand: only used with model"),
                    std::string::npos)
              << error.what();
          throw;
        }
      },
      Error);
}

}  // namespace
}  // namespace slide
