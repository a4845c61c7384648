// The checkpoint module: every kind round-trips bit for bit, every class of bad file is
// rejected with a one-line message naming the dataset, and a failed write leaves an
// existing checkpoint byte-identical. Bad files are made by writing a good one and then
// damaging it with the HDF5 C API directly, as a foreign tool would.
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include "common/base/error.hpp"
#include "common/io/checkpoint.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Sample checkpoints: small, but every field holds distinct, awkward values (negative
// zero, a subnormal, large and tiny magnitudes, irrational numbers) so that any
// conversion, rounding or mix-up of fields shows. "Large" stays below the smallest of
// the schema's magnitude limits (10⁵ m/s for velocities): beyond them nothing is written.

double awkward(std::size_t i) {
  static const double specials[] = {-0.0,
                                    std::numeric_limits<double>::denorm_min(),
                                    -9.75e4,
                                    std::numbers::pi,
                                    1.0 / 3.0,
                                    -2.5e-17,
                                    99999.99999999999,
                                    std::numbers::e};
  const std::size_t n = std::size(specials);
  return i % 3 == 0 ? specials[(i / 3) % n] : std::sqrt(2.0) * static_cast<double>(i) - 7.25;
}

/// Fills each field from its own stretch of the awkward sequence.
struct Filler {
  std::size_t next = 0;
  double scalar() { return awkward(next++); }
  Vec2 vec2() {
    const double a = scalar();
    return {a, scalar()};
  }
  Vec4 vec4() {
    const double a = scalar(), b = scalar(), c = scalar();
    return {a, b, c, scalar()};
  }
  std::vector<double> scalars(std::size_t n) {
    std::vector<double> v(n);
    for (auto& x : v) x = scalar();
    return v;
  }
  /// Values > 0 (volumes, sizes): the magnitudes of the sequence, kept off zero.
  std::vector<double> positives(std::size_t n) {
    std::vector<double> v(n);
    for (auto& x : v) x = std::abs(scalar()) + std::numeric_limits<double>::denorm_min();
    return v;
  }
  std::vector<Vec2> positive_vec2s(std::size_t n) {
    std::vector<Vec2> v(n);
    for (auto& x : v) {
      const double a = std::abs(scalar()) + std::numeric_limits<double>::denorm_min();
      x = {a, std::abs(scalar()) + std::numeric_limits<double>::denorm_min()};
    }
    return v;
  }
  std::vector<Vec2> vec2s(std::size_t n) {
    std::vector<Vec2> v(n);
    for (auto& x : v) x = vec2();
    return v;
  }
  std::vector<Vec4> vec4s(std::size_t n) {
    std::vector<Vec4> v(n);
    for (auto& x : v) x = vec4();
    return v;
  }
  std::vector<MaterialState> states(std::size_t n) {
    std::vector<MaterialState> v(n);
    for (auto& s : v) {
      s.plastic_shear_strain = std::abs(scalar());
      s.plastic_volumetric_strain = scalar();
    }
    return v;
  }
};

MaterialTable sample_materials() {
  Material clay = synthetic::material("weak clay", MaterialModel::mohr_coulomb, 1900.0, 2.0e7, 0.3,
                                      25.0, 1.0e4 / 3.0);
  clay.tension_cutoff = 1234.5;
  // UTF-8 survives.
  const Material rock =
      synthetic::material("bedrock ü", MaterialModel::linear_elastic, 2650.0, 1.0e10, 0.25, 40.0);
  return {clay, rock};
}

/// A 3×2 block of quads (or each quad split into two triangles) with every field set.
FemCheckpoint sample_fem(ElementType type) {
  FemCheckpoint c;
  c.header.kind = CheckpointKind::fem;
  c.header.producer = "fem-solve 0.1.0";
  c.header.time = 2.0;
  c.header.step = 1234;
  c.header.case_name = "test-slope";
  c.header.pe0 = -1.0 / 7.0 * 1.0e9;

  Mesh& mesh = c.mesh;
  mesh.element_type = type;
  const int nx = 3, ny = 2;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) mesh.nodes.emplace_back(0.5 * i, 0.1 + 0.75 * j);
  }
  auto node = [&](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Index a = node(i, j), b = node(i + 1, j), d = node(i + 1, j + 1), e = node(i, j + 1);
      if (type == ElementType::tri3) {
        mesh.connectivity.insert(mesh.connectivity.end(), {a, b, d, a, d, e});
        mesh.material_id.insert(mesh.material_id.end(), {j, 1 - j});
      } else {
        mesh.connectivity.insert(mesh.connectivity.end(), {a, b, d, e});
        mesh.material_id.push_back(i % 2);
      }
    }
  }
  // Not alphabetical: a restart must get them back in this order.
  mesh.node_sets = {{"left", {node(0, 0), node(0, 1), node(0, 2)}, Vec2(-1.0, 0.0)},
                    {"right", {node(3, 2), node(3, 1), node(3, 0)}, Vec2(1.0, 0.0)},
                    {"base", {node(0, 0), node(1, 0), node(2, 0), node(3, 0)}, Vec2(0.0, -1.0)},
                    {"empty set", {}, Vec2(std::sqrt(0.5), std::sqrt(0.5))}};
  c.boundary_conditions = {BoundaryCondition::roller, BoundaryCondition::fixed,
                           BoundaryCondition::friction, BoundaryCondition::free};
  c.friction_coefficient = std::tan(20.0 * std::numbers::pi / 180.0);

  Filler f;
  const std::size_t n_nodes = mesh.nodes.size();
  const std::size_t n_elements = mesh.material_id.size();
  c.coordinates = f.vec2s(n_nodes);
  c.displacement = f.vec2s(n_nodes);
  c.velocity = f.vec2s(n_nodes);
  c.acceleration = f.vec2s(n_nodes);
  c.pore_pressure = f.scalars(n_nodes);
  c.jacobian_ratio = f.scalars(n_elements);
  // Optional: the triangles' sample goes without it, as a file written before it existed.
  if (type != ElementType::tri3) c.scaled_jacobian = f.scalars(n_elements);
  c.volume_reference = f.positives(n_elements);
  c.volume = f.scalars(n_elements);
  if (type == ElementType::quad4_1gp) c.hourglass_force = f.vec2s(n_elements);

  for (std::size_t e = 0; e < n_elements; ++e) {
    for (const auto& point : quadrature_rule(type)) {
      c.gauss_element.push_back(static_cast<Index>(e));
      c.gauss_local_coordinates.push_back(point.xi);
      c.gauss_weight.push_back(point.weight);
    }
  }
  const std::size_t n_gp = c.gauss_element.size();
  c.gauss_coordinates = f.vec2s(n_gp);
  c.stress = f.vec4s(n_gp);
  c.strain = f.vec4s(n_gp);
  c.eps_q = f.positives(n_gp);
  c.material_state = f.states(n_gp);

  c.materials = sample_materials();
  c.solver = {{"stage", std::string("failure")},
              {"time_step", 1.2e-3},
              {"steps_per_output", std::int64_t{100}},
              {"damping", -0.0}};
  return c;
}

ParticleCheckpoint sample_particles(CheckpointKind kind, std::size_t n = 7) {
  ParticleCheckpoint c;
  c.header.kind = kind;
  c.header.producer = kind == CheckpointKind::particles ? "fem2mpm 0.1.0" : "mpm-solve 0.1.0";
  c.header.time = kind == CheckpointKind::particles ? 2.0 : 3.5;
  c.header.step = kind == CheckpointKind::particles ? 0 : 777;
  c.header.case_name = "test-slope";
  c.header.pe0 = 5.0e8 + 1.0 / 3.0;

  Filler f;
  Particles& p = c.particles;
  p.coordinates = f.vec2s(n);
  p.displacement = f.vec2s(n);
  p.velocity = f.vec2s(n);
  p.stress = f.vec4s(n);
  p.strain = f.vec4s(n);
  p.eps_q = f.positives(n);
  p.pore_pressure = f.scalars(n);
  p.size = f.positive_vec2s(n);
  p.state = f.states(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.volume.push_back(0.01 + std::numbers::pi * 1.0e-3 * static_cast<double>(i));
    p.mass.push_back(std::numeric_limits<double>::denorm_min() + static_cast<double>(i) / 3.0);
    p.material_id.push_back(static_cast<std::int32_t>(i % 2));
    p.element.push_back(kind == CheckpointKind::particles ? static_cast<std::int64_t>(i / 4) : -1);
    p.id.push_back(static_cast<std::int64_t>(1000 + 3 * i));
  }
  c.materials = sample_materials();
  if (kind == CheckpointKind::particles) {
    c.transfer = {2.0, "2x2", "rbf-local", "linear", 0.35, 16};
  } else {
    c.solver = {{"grid_spacing", 0.25}, {"grid_origin_x", -1.0}, {"shape_function", "gimp"}};
  }
  return c;
}

// ---------------------------------------------------------------------------------------
// Bit-for-bit comparison.

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

void expect_identical(std::span<const double> a, std::span<const double> b,
                      const std::string& name) {
  ASSERT_EQ(a.size(), b.size()) << name;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(bits(a[i]), bits(b[i])) << name << "[" << i << "]: " << a[i] << " vs " << b[i];
  }
}

template <int K>
void expect_identical(const std::vector<Eigen::Matrix<double, K, 1>>& a,
                      const std::vector<Eigen::Matrix<double, K, 1>>& b, const std::string& name) {
  ASSERT_EQ(a.size(), b.size()) << name;
  for (std::size_t i = 0; i < a.size(); ++i) {
    expect_identical(std::span<const double>(a[i].data(), K),
                     std::span<const double>(b[i].data(), K), name + " row " + std::to_string(i));
  }
}

void expect_identical(const std::vector<MaterialState>& a, const std::vector<MaterialState>& b,
                      const std::string& name) {
  ASSERT_EQ(a.size(), b.size()) << name;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(bits(a[i].plastic_shear_strain), bits(b[i].plastic_shear_strain)) << name << i;
    EXPECT_EQ(bits(a[i].plastic_volumetric_strain), bits(b[i].plastic_volumetric_strain))
        << name << i;
  }
}

void expect_identical(const CheckpointHeader& a, const CheckpointHeader& b) {
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(b.schema_version, checkpoint_schema_version);
  EXPECT_EQ(a.producer, b.producer);
  EXPECT_EQ(bits(a.time), bits(b.time));
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.case_name, b.case_name);
  EXPECT_EQ(bits(a.pe0), bits(b.pe0));
}

void expect_identical(const MaterialTable& a, const MaterialTable& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].model, b[i].model);
    for (auto field : {&Material::density, &Material::youngs_modulus, &Material::poisson_ratio,
                       &Material::friction_angle, &Material::cohesion, &Material::dilation_angle,
                       &Material::tension_cutoff}) {
      EXPECT_EQ(bits(a[i].*field), bits(b[i].*field)) << "material " << i;
    }
  }
}

void expect_identical(const SolverSettings& a, const SolverSettings& b) {
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [key, value] : a) {
    ASSERT_TRUE(b.contains(key)) << key;
    const SettingValue& other = b.at(key);
    ASSERT_EQ(value.index(), other.index()) << key;
    if (const double* x = std::get_if<double>(&value)) {
      EXPECT_EQ(bits(*x), bits(std::get<double>(other))) << key;
    } else {
      EXPECT_EQ(value, other) << key;
    }
  }
}

void expect_identical(const TransferSettings& a, const TransferSettings& b) {
  EXPECT_EQ(bits(a.transfer_time), bits(b.transfer_time));
  EXPECT_EQ(a.particles_per_element, b.particles_per_element);
  EXPECT_EQ(a.stress_interpolation, b.stress_interpolation);
  EXPECT_EQ(a.rbf_polynomial, b.rbf_polynomial);
  EXPECT_EQ(bits(a.rbf_shape), bits(b.rbf_shape));
  EXPECT_EQ(a.rbf_neighbours, b.rbf_neighbours);
}

void expect_identical(const FemCheckpoint& a, const FemCheckpoint& b) {
  expect_identical(a.header, b.header);
  EXPECT_EQ(a.mesh.element_type, b.mesh.element_type);
  expect_identical<2>(a.mesh.nodes, b.mesh.nodes, "reference_coordinates");
  EXPECT_EQ(a.mesh.connectivity, b.mesh.connectivity);
  EXPECT_EQ(a.mesh.material_id, b.mesh.material_id);
  ASSERT_EQ(a.mesh.node_sets.size(), b.mesh.node_sets.size());
  for (std::size_t i = 0; i < a.mesh.node_sets.size(); ++i) {
    EXPECT_EQ(a.mesh.node_sets[i].name, b.mesh.node_sets[i].name);
    EXPECT_EQ(a.mesh.node_sets[i].nodes, b.mesh.node_sets[i].nodes);
    expect_identical<2>({a.mesh.node_sets[i].normal}, {b.mesh.node_sets[i].normal}, "normal");
  }
  EXPECT_EQ(a.boundary_conditions, b.boundary_conditions);
  EXPECT_EQ(bits(a.friction_coefficient), bits(b.friction_coefficient));
  expect_identical<2>(a.coordinates, b.coordinates, "coordinates");
  expect_identical<2>(a.displacement, b.displacement, "displacement");
  expect_identical<2>(a.velocity, b.velocity, "velocity");
  expect_identical<2>(a.acceleration, b.acceleration, "acceleration");
  expect_identical(a.pore_pressure, b.pore_pressure, "pore_pressure");
  expect_identical(a.jacobian_ratio, b.jacobian_ratio, "jacobian_ratio");
  expect_identical(a.scaled_jacobian, b.scaled_jacobian, "scaled_jacobian");
  expect_identical(a.volume_reference, b.volume_reference, "volume_reference");
  expect_identical(a.volume, b.volume, "volume");
  expect_identical<2>(a.hourglass_force, b.hourglass_force, "hourglass_force");
  EXPECT_EQ(a.gauss_element, b.gauss_element);
  expect_identical<2>(a.gauss_local_coordinates, b.gauss_local_coordinates, "local_coordinates");
  expect_identical<2>(a.gauss_coordinates, b.gauss_coordinates, "gauss coordinates");
  expect_identical(a.gauss_weight, b.gauss_weight, "weight");
  expect_identical<4>(a.stress, b.stress, "stress");
  expect_identical<4>(a.strain, b.strain, "strain");
  expect_identical(a.eps_q, b.eps_q, "eps_q");
  expect_identical(a.material_state, b.material_state, "state");
  expect_identical(a.materials, b.materials);
  expect_identical(a.solver, b.solver);
}

void expect_identical(const ParticleCheckpoint& a, const ParticleCheckpoint& b) {
  expect_identical(a.header, b.header);
  const Particles& p = a.particles;
  const Particles& q = b.particles;
  expect_identical<2>(p.coordinates, q.coordinates, "coordinates");
  expect_identical<2>(p.displacement, q.displacement, "displacement");
  expect_identical<2>(p.velocity, q.velocity, "velocity");
  expect_identical<4>(p.stress, q.stress, "stress");
  expect_identical<4>(p.strain, q.strain, "strain");
  expect_identical(p.eps_q, q.eps_q, "eps_q");
  expect_identical(p.pore_pressure, q.pore_pressure, "pore_pressure");
  expect_identical(p.volume, q.volume, "volume");
  expect_identical(p.mass, q.mass, "mass");
  expect_identical<2>(p.size, q.size, "size");
  EXPECT_EQ(p.material_id, q.material_id);
  EXPECT_EQ(p.element, q.element);
  EXPECT_EQ(p.id, q.id);
  expect_identical(p.state, q.state, "state");
  expect_identical<4>(p.affine_velocity, q.affine_velocity, "affine_velocity");
  expect_identical(a.materials, b.materials);
  expect_identical(a.transfer, b.transfer);
  expect_identical(a.solver, b.solver);
}

// ---------------------------------------------------------------------------------------
// A scratch folder per test, and the HDF5 C API to damage files.

class Checkpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::path(::testing::TempDir()) /
              fmt::format("slide-checkpoint-{}-{}", info->name(), ::getpid());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  fs::path file(const std::string& name) const { return folder_ / name; }

  fs::path folder_;
};

/// Opens a checkpoint read-write with the plain C API and applies one kind of damage.
class Damage {
 public:
  explicit Damage(const fs::path& path) : file_(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)) {
    EXPECT_GE(file_, 0) << path;
  }
  ~Damage() { H5Fclose(file_); }
  Damage(const Damage&) = delete;
  Damage& operator=(const Damage&) = delete;

  void delete_link(const std::string& path) {
    EXPECT_GE(H5Ldelete(file_, path.c_str(), H5P_DEFAULT), 0);
  }

  void delete_attribute(const std::string& object, const std::string& name) {
    EXPECT_GE(H5Adelete_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT), 0);
  }

  void set_string_attribute(const std::string& object, const std::string& name,
                            const std::string& value) {
    if (H5Aexists_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT) > 0) {
      delete_attribute(object, name);
    }
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attribute = H5Acreate_by_name(file_, object.c_str(), name.c_str(), type, space,
                                              H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const char* text = value.c_str();
    EXPECT_GE(H5Awrite(attribute, type, &text), 0);
    H5Aclose(attribute);
    H5Sclose(space);
    H5Tclose(type);
  }

  /// A fixed-length, space-padded string, as Fortran or numpy bytes would store it.
  void set_fixed_string_attribute(const std::string& object, const std::string& name,
                                  const std::string& value, std::size_t length) {
    if (H5Aexists_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT) > 0) {
      delete_attribute(object, name);
    }
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, length);
    H5Tset_strpad(type, H5T_STR_SPACEPAD);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attribute = H5Acreate_by_name(file_, object.c_str(), name.c_str(), type, space,
                                              H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::string padded = value;
    padded.resize(length, ' ');
    EXPECT_GE(H5Awrite(attribute, type, padded.data()), 0);
    H5Aclose(attribute);
    H5Sclose(space);
    H5Tclose(type);
  }

  /// Replaces attribute `name` by a 32-bit integer one.
  void set_int32_attribute_anew(const std::string& object, const std::string& name,
                                std::int32_t value) {
    delete_attribute(object, name);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attribute = H5Acreate_by_name(file_, object.c_str(), name.c_str(), H5T_STD_I32BE,
                                              space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(H5Awrite(attribute, H5T_NATIVE_INT32, &value), 0);
    H5Aclose(attribute);
    H5Sclose(space);
  }

  void set_int_attribute(const std::string& object, const std::string& name, std::int64_t value) {
    const hid_t attribute =
        H5Aopen_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(H5Awrite(attribute, H5T_NATIVE_INT64, &value), 0);
    H5Aclose(attribute);
  }

  /// Replaces dataset `path` by one of another shape (`type`: H5T_NATIVE_DOUBLE or
  /// H5T_NATIVE_INT64), filled with ones.
  void replace_dataset(const std::string& path, std::vector<hsize_t> shape, hid_t type) {
    delete_link(path);
    hsize_t count = 1;
    for (auto extent : shape) count *= extent;
    const hid_t space = H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr);
    const hid_t dataset =
        H5Dcreate2(file_, path.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(dataset, 0);
    const std::vector<double> ones(count, 1.0);
    const std::vector<std::int64_t> int_ones(count, 1);
    const void* data = H5Tequal(type, H5T_NATIVE_DOUBLE) > 0
                           ? static_cast<const void*>(ones.data())
                           : static_cast<const void*>(int_ones.data());
    EXPECT_GE(H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), 0);
    H5Dclose(dataset);
    H5Sclose(space);
  }

  /// Overwrites the element at flat index `index` of a float dataset.
  void set_double(const std::string& path, std::size_t index, double value) {
    modify<double>(path, H5T_NATIVE_DOUBLE, [&](std::vector<double>& v) { v.at(index) = value; });
  }
  /// Overwrites the element at flat index `index` of an integer dataset.
  void set_int(const std::string& path, std::size_t index, std::int64_t value) {
    modify<std::int64_t>(path, H5T_NATIVE_INT64,
                         [&](std::vector<std::int64_t>& v) { v.at(index) = value; });
  }

 private:
  template <typename T>
  void modify(const std::string& path, hid_t type, const std::function<void(std::vector<T>&)>& f) {
    const hid_t dataset = H5Dopen2(file_, path.c_str(), H5P_DEFAULT);
    ASSERT_GE(dataset, 0) << path;
    const hid_t space = H5Dget_space(dataset);
    std::vector<T> values(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    EXPECT_GE(H5Dread(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
    f(values);
    EXPECT_GE(H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
    H5Sclose(space);
    H5Dclose(dataset);
  }

  hid_t file_;
};

/// The message of the Error that `read` throws (fails the test if none).
std::string error_of(const std::function<void()>& read) {
  try {
    read();
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
    return message;
  }
  ADD_FAILURE() << "no Error thrown";
  return {};
}

std::string fem_error(const fs::path& path) {
  return error_of([&] { read_fem_checkpoint(path); });
}
std::string particle_error(const fs::path& path) {
  return error_of([&] { read_particle_checkpoint(path); });
}

std::string bytes_of(const fs::path& path) {
  std::string bytes(fs::file_size(path), '\0');
  std::ifstream in(path, std::ios::binary);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return bytes;
}

// ---------------------------------------------------------------------------------------
// Round trips

TEST_F(Checkpoint, KindNames) {
  EXPECT_EQ(to_string(CheckpointKind::fem), "fem");
  EXPECT_EQ(to_string(CheckpointKind::particles), "particles");
  EXPECT_EQ(to_string(CheckpointKind::mpm), "mpm");
}

TEST_F(Checkpoint, FemQuad4TwoByTwoRoundTripIsExact) {
  const FemCheckpoint written = sample_fem(ElementType::quad4_2x2);
  ASSERT_EQ(written.gauss_element.size(), 24u);
  write_checkpoint(file("fem_t2.000.h5"), written);
  expect_identical(written, read_fem_checkpoint(file("fem_t2.000.h5")));
}

TEST_F(Checkpoint, FemQuad4OnePointWithHourglassForcesRoundTripIsExact) {
  const FemCheckpoint written = sample_fem(ElementType::quad4_1gp);
  ASSERT_FALSE(written.hourglass_force.empty());
  write_checkpoint(file("fem.h5"), written);
  const FemCheckpoint read = read_fem_checkpoint(file("fem.h5"));
  EXPECT_EQ(read.mesh.element_type, ElementType::quad4_1gp);
  expect_identical(written, read);
}

TEST_F(Checkpoint, FemTri3RoundTripIsExact) {
  const FemCheckpoint written = sample_fem(ElementType::tri3);
  ASSERT_EQ(written.mesh.connectivity.size(), 12u * 3u);
  write_checkpoint(file("fem.h5"), written);
  const FemCheckpoint read = read_fem_checkpoint(file("fem.h5"));
  EXPECT_EQ(read.mesh.element_type, ElementType::tri3);
  EXPECT_TRUE(read.hourglass_force.empty());
  EXPECT_TRUE(read.scaled_jacobian.empty());  // absent dataset: read as none
  expect_identical(written, read);
}

TEST_F(Checkpoint, ParticlesRoundTripIsExact) {
  const ParticleCheckpoint written = sample_particles(CheckpointKind::particles);
  write_checkpoint(file("particles.h5"), written);
  expect_identical(written, read_particle_checkpoint(file("particles.h5")));
}

TEST_F(Checkpoint, MpmRoundTripIsExact) {
  const ParticleCheckpoint written = sample_particles(CheckpointKind::mpm);
  write_checkpoint(file("mpm_t3.500.h5"), written);
  expect_identical(written, read_particle_checkpoint(file("mpm_t3.500.h5")));
  // A pure MPM checkpoint has no transfer; one continuing a transfer keeps it.
  ParticleCheckpoint continued = written;
  continued.transfer = {2.0, "16", "element", "none", 0.0, 0};
  write_checkpoint(file("mpm_continued.h5"), continued);
  expect_identical(continued, read_particle_checkpoint(file("mpm_continued.h5")));
}

// APIC's affine velocity is optional: written when the particles carry it, read back bit
// for bit; a file without it reads as particles without it (C_p = 0 for an APIC run).
TEST_F(Checkpoint, AffineVelocityIsOptionalAndRoundTripsExactly) {
  ParticleCheckpoint written = sample_particles(CheckpointKind::mpm);
  Filler f;
  written.particles.affine_velocity = f.vec4s(written.particles.count());
  write_checkpoint(file("mpm_apic.h5"), written);
  const ParticleCheckpoint read = read_particle_checkpoint(file("mpm_apic.h5"));
  ASSERT_EQ(read.particles.affine_velocity.size(), written.particles.count());
  expect_identical(written, read);

  const ParticleCheckpoint without = sample_particles(CheckpointKind::particles);
  write_checkpoint(file("particles.h5"), without);
  EXPECT_TRUE(read_particle_checkpoint(file("particles.h5")).particles.affine_velocity.empty());

  Damage(file("mpm_apic.h5"))
      .replace_dataset("/particles/affine_velocity_gradient", {7, 2}, H5T_NATIVE_DOUBLE);
  EXPECT_EQ(particle_error(file("mpm_apic.h5")),
            file("mpm_apic.h5").string() +
                ": /particles/affine_velocity_gradient: shape 7×2, expected 7×4");
}

// Read in parts (each MPI rank its own rows): the parts are contiguous runs of rows,
// [⌊k n/N⌋, ⌊(k + 1) n/N⌋), which put together are the whole file bit for bit; each is
// validated, and a bad value is named by its row in the file.
TEST_F(Checkpoint, ParticleRowsAreReadInParts) {
  ParticleCheckpoint written = sample_particles(CheckpointKind::mpm, 11);
  Filler f;
  written.particles.affine_velocity = f.vec4s(written.particles.count());
  write_checkpoint(file("mpm.h5"), written);
  // Rows [first, first + count) of every field of the written particles.
  auto rows_of = [&](std::size_t first, std::size_t count) {
    ParticleCheckpoint expected = written;
    Particles& p = expected.particles;
    auto slice = [&](auto& field) {
      using Field = std::remove_reference_t<decltype(field)>;
      field = Field(field.begin() + static_cast<std::ptrdiff_t>(first),
                    field.begin() + static_cast<std::ptrdiff_t>(first + count));
    };
    slice(p.coordinates), slice(p.displacement), slice(p.velocity), slice(p.stress);
    slice(p.strain), slice(p.eps_q), slice(p.pore_pressure), slice(p.volume), slice(p.mass);
    slice(p.size), slice(p.material_id), slice(p.element), slice(p.id), slice(p.state);
    slice(p.affine_velocity);
    return expected;
  };
  for (int parts : {1, 2, 3, 5, 11, 13}) {
    std::size_t next = 0;
    for (int k = 0; k < parts; ++k) {
      const ParticleCheckpoint part = read_particle_checkpoint(file("mpm.h5"), {k, parts});
      EXPECT_EQ(part.file_rows, 11u);
      EXPECT_EQ(part.first_row, next) << "part " << k << " of " << parts;
      EXPECT_EQ(part.first_row, static_cast<std::size_t>(k) * 11 / static_cast<std::size_t>(parts));
      expect_identical(rows_of(part.first_row, part.particles.count()), part);
      next = part.first_row + part.particles.count();
    }
    EXPECT_EQ(next, 11u) << parts << " parts";
  }
  Damage(file("mpm.h5")).set_double("/particles/volume", 8, -1.0);
  EXPECT_NO_THROW(read_particle_checkpoint(file("mpm.h5"), {0, 2}));  // rows 0–4
  EXPECT_EQ(
      error_of([&] {
        read_particle_checkpoint(file("mpm.h5"), {1, 2});
      }),
      file("mpm.h5").string() + ": /particles/volume: particle 8 has volume -1, expected > 0");
  EXPECT_THROW(read_particle_checkpoint(file("mpm.h5"), {2, 2}), Error);
}

TEST_F(Checkpoint, EmptyParticleSetRoundTrips) {
  const ParticleCheckpoint written = sample_particles(CheckpointKind::mpm, 0);
  write_checkpoint(file("mpm.h5"), written);
  expect_identical(written, read_particle_checkpoint(file("mpm.h5")));
}

TEST_F(Checkpoint, HeaderIsReadAlone) {
  write_checkpoint(file("particles.h5"), sample_particles(CheckpointKind::particles));
  const CheckpointHeader header = read_checkpoint_header(file("particles.h5"));
  EXPECT_EQ(header.kind, CheckpointKind::particles);
  EXPECT_EQ(header.producer, "fem2mpm 0.1.0");
  EXPECT_EQ(header.case_name, "test-slope");
  EXPECT_EQ(header.time, 2.0);
}

TEST_F(Checkpoint, RewritingReplacesTheFile) {
  FemCheckpoint c = sample_fem(ElementType::quad4_2x2);
  write_checkpoint(file("fem.h5"), c);
  c.header.time = 4.0;
  c.stress[3] = Vec4(-1.0, -2.0, -3.0, 0.5);
  write_checkpoint(file("fem.h5"), c);
  expect_identical(c, read_fem_checkpoint(file("fem.h5")));
}

// The names every reader relies on (docs/contract.md), read with the plain C API; every dataset
// carries a `units` string.
TEST_F(Checkpoint, FileCarriesTheContractAttributesAndUnitsOnEveryDataset) {
  write_checkpoint(file("fem.h5"), sample_fem(ElementType::quad4_2x2));
  const hid_t f = H5Fopen(file("fem.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (const char* name : {"schema", "schema_version", "producer", "kind", "time", "step",
                           "dimension", "case", "pe0"}) {
    EXPECT_GT(H5Aexists(f, name), 0) << name;
  }
  std::int64_t dimension = 0;
  const hid_t a = H5Aopen(f, "dimension", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_INT64, &dimension);
  H5Aclose(a);
  EXPECT_EQ(dimension, 2);

  struct Visit {
    std::vector<std::string> datasets;
    std::vector<std::string> without_units;
  } visit;
  auto each = [](hid_t root, const char* name, const auto*, void* data) -> herr_t {
    auto& v = *static_cast<Visit*>(data);
    const hid_t object = H5Oopen(root, name, H5P_DEFAULT);
    if (H5Iget_type(object) == H5I_DATASET) {
      v.datasets.emplace_back(name);
      if (H5Aexists(object, "units") <= 0) v.without_units.emplace_back(name);
    }
    H5Oclose(object);
    return 0;
  };
  ASSERT_GE(H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, each, &visit), 0);
  H5Fclose(f);
  // 6 nodes + 6 elements (scaled_jacobian included) + 9 Gauss points + 4 sets
  EXPECT_EQ(visit.datasets.size(), 25u);
  EXPECT_TRUE(visit.without_units.empty()) << visit.without_units.front();
}

// Files from other tools may store strings fixed-length and whole numbers as integers.
TEST_F(Checkpoint, FixedLengthStringsAndIntegerNumbersFromOtherToolsAreRead) {
  const fs::path path = file("fem.h5");
  const FemCheckpoint written = sample_fem(ElementType::tri3);
  write_checkpoint(path, written);
  {
    Damage damage(path);
    damage.set_fixed_string_attribute("/", "kind", "fem", 8);
    damage.set_fixed_string_attribute("/materials/0", "name", "weak clay", 16);
    damage.set_int32_attribute_anew("/", "time", 2);
    damage.set_int32_attribute_anew("/", "step", 1234);
  }
  expect_identical(written, read_fem_checkpoint(path));
}

// ---------------------------------------------------------------------------------------
// Bad files

TEST_F(Checkpoint, MissingFileIsRejected) {
  EXPECT_NE(fem_error(file("nothing.h5")).find("nothing.h5: cannot open: no such file"),
            std::string::npos);
}

TEST_F(Checkpoint, NonHdf5OrTruncatedFileIsRejected) {
  std::ofstream(file("text.h5")) << "schema = fem-mpm-checkpoint\n";
  EXPECT_EQ(fem_error(file("text.h5")), file("text.h5").string() + ": not an HDF5 file");
  EXPECT_NE(error_of([&] { read_checkpoint_header(file("text.h5")); }).find("not an HDF5 file"),
            std::string::npos);
  // A checkpoint cut short, as a copy interrupted half way would leave it.
  write_checkpoint(file("mpm.h5"), sample_particles(CheckpointKind::mpm));
  const std::string bytes = bytes_of(file("mpm.h5"));
  std::ofstream(file("cut.h5"), std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  EXPECT_NE(particle_error(file("cut.h5")).find("cut.h5: cannot open as HDF5 (truncated file"),
            std::string::npos);
}

TEST_F(Checkpoint, WrongSchemaIsRejected) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::tri3));
  Damage(path).set_string_attribute("/", "schema", "some-other-format");
  EXPECT_EQ(fem_error(path), path.string() +
                                 ": attribute schema is \"some-other-format\", expected "
                                 "\"fem-mpm-checkpoint\"");
  Damage(path).delete_attribute("/", "schema");
  EXPECT_NE(fem_error(path).find("attribute schema missing"), std::string::npos);
}

TEST_F(Checkpoint, NewerSchemaVersionIsRejectedAsNewer) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::tri3));
  Damage(path).set_int_attribute("/", "schema_version", 99);
  const std::string message = fem_error(path);
  EXPECT_NE(message.find("schema_version 99 is newer"), std::string::npos) << message;
  EXPECT_NE(error_of([&] { read_checkpoint_header(path); }).find("newer"), std::string::npos);
  Damage(path).set_int_attribute("/", "schema_version", 0);
  EXPECT_NE(fem_error(path).find("unknown schema_version 0, expected 1"), std::string::npos);
}

TEST_F(Checkpoint, WrongKindIsRejected) {
  const fs::path fem = file("fem.h5");
  write_checkpoint(fem, sample_fem(ElementType::quad4_2x2));
  EXPECT_EQ(particle_error(fem),
            fem.string() + ": is a fem checkpoint, expected kind particles or mpm");
  Damage(fem).set_string_attribute("/", "kind", "particles");
  EXPECT_EQ(fem_error(fem), fem.string() + ": is a particles checkpoint, expected kind fem");
  Damage(fem).set_string_attribute("/", "kind", "vtk");
  EXPECT_NE(fem_error(fem).find("attribute kind is \"vtk\""), std::string::npos);

  const fs::path particles = file("particles.h5");
  write_checkpoint(particles, sample_particles(CheckpointKind::particles));
  EXPECT_EQ(fem_error(particles),
            particles.string() + ": is a particles checkpoint, expected kind fem");
}

TEST_F(Checkpoint, MissingDatasetIsNamed) {
  const fs::path path = file("fem.h5");
  for (const std::string name :
       {"/gauss_points/stress", "/nodes/reference_coordinates", "/elements/connectivity",
        "/gauss_points/element", "/gauss_points/state/plastic_volumetric_strain",
        "/boundary/base/nodes"}) {
    write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
    Damage(path).delete_link(name);
    EXPECT_EQ(fem_error(path), path.string() + ": " + name + ": dataset missing");
  }
  const fs::path particles = file("particles.h5");
  write_checkpoint(particles, sample_particles(CheckpointKind::particles));
  Damage(particles).delete_link("/particles/id");
  EXPECT_EQ(particle_error(particles), particles.string() + ": /particles/id: dataset missing");
}

TEST_F(Checkpoint, MissingAttributeOrGroupIsNamed) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).delete_attribute("/materials/1", "youngs_modulus");
  EXPECT_EQ(fem_error(path), path.string() + ": /materials/1: attribute youngs_modulus missing");

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).delete_attribute("/elements/connectivity", "integration");
  EXPECT_EQ(fem_error(path),
            path.string() + ": /elements/connectivity: attribute integration missing");

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).delete_attribute("/", "pe0");
  EXPECT_EQ(fem_error(path), path.string() + ": attribute pe0 missing");

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).delete_link("/boundary");
  EXPECT_EQ(fem_error(path), path.string() + ": /boundary: group missing");

  const fs::path particles = file("particles.h5");
  write_checkpoint(particles, sample_particles(CheckpointKind::particles));
  Damage(particles).delete_attribute("/transfer", "rbf_shape");
  EXPECT_EQ(particle_error(particles),
            particles.string() + ": /transfer: attribute rbf_shape missing");
}

TEST_F(Checkpoint, WrongShapeIsNamedWithTheExpectedShape) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).replace_dataset("/gauss_points/stress", {24, 3}, H5T_NATIVE_DOUBLE);
  EXPECT_EQ(fem_error(path), path.string() + ": /gauss_points/stress: shape 24×3, expected 24×4");

  // Row counts follow the defining datasets.
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).replace_dataset("/nodes/velocity", {11, 2}, H5T_NATIVE_DOUBLE);
  EXPECT_EQ(fem_error(path), path.string() + ": /nodes/velocity: shape 11×2, expected 12×2");

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).replace_dataset("/elements/volume", {6, 1}, H5T_NATIVE_DOUBLE);
  EXPECT_EQ(fem_error(path), path.string() + ": /elements/volume: shape 6×1, expected 6");

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).replace_dataset("/nodes/reference_coordinates", {12, 3}, H5T_NATIVE_DOUBLE);
  EXPECT_EQ(fem_error(path),
            path.string() + ": /nodes/reference_coordinates: shape 12×3, expected n_nodes×2");

  // A tri3 connectivity under a quad4 rule.
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  {
    Damage damage(path);
    damage.replace_dataset("/elements/connectivity", {6, 3}, H5T_NATIVE_INT64);
    damage.set_string_attribute("/elements/connectivity", "type", "quad4");
    damage.set_string_attribute("/elements/connectivity", "integration", "quad4-2x2");
  }
  EXPECT_NE(fem_error(path).find("/elements/connectivity: shape 6×3, expected n_elements×4"),
            std::string::npos);

  const fs::path particles = file("particles.h5");
  write_checkpoint(particles, sample_particles(CheckpointKind::particles));
  Damage(particles).replace_dataset("/particles/mass", {8}, H5T_NATIVE_DOUBLE);
  EXPECT_EQ(particle_error(particles),
            particles.string() + ": /particles/mass: shape 8, expected 7");
}

TEST_F(Checkpoint, WrongTypeClassIsNamed) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::tri3));
  Damage(path).replace_dataset("/nodes/pore_pressure", {12}, H5T_NATIVE_INT64);
  EXPECT_EQ(fem_error(path), path.string() +
                                 ": /nodes/pore_pressure: type class integer, expected floating "
                                 "point");

  write_checkpoint(path, sample_fem(ElementType::tri3));
  Damage(path).replace_dataset("/elements/material_id", {12}, H5T_NATIVE_DOUBLE);
  EXPECT_EQ(fem_error(path), path.string() +
                                 ": /elements/material_id: type class floating point, expected "
                                 "integer");

  write_checkpoint(path, sample_fem(ElementType::tri3));
  Damage(path).set_string_attribute("/", "step", "three");
  EXPECT_EQ(fem_error(path),
            path.string() + ": attribute step: type class string, expected integer");
}

TEST_F(Checkpoint, NonFiniteValueIsNamedWithItsRow) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).set_double("/gauss_points/stress", 4 * 17 + 2, std::nan(""));
  EXPECT_EQ(fem_error(path),
            path.string() + ": /gauss_points/stress: Gauss point 17 is not finite (nan)");

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).set_double("/nodes/coordinates", 2 * 5 + 1, -HUGE_VAL);
  EXPECT_EQ(fem_error(path), path.string() + ": /nodes/coordinates: node 5 is not finite (-inf)");

  const fs::path particles = file("particles.h5");
  write_checkpoint(particles, sample_particles(CheckpointKind::mpm));
  Damage(particles).set_double("/particles/state/plastic_shear_strain", 6, HUGE_VAL);
  EXPECT_EQ(particle_error(particles),
            particles.string() +
                ": /particles/state/plastic_shear_strain: particle 6 is not finite (inf)");
}

TEST_F(Checkpoint, IndexOutOfRangeIsNamed) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).set_int("/elements/connectivity", 4 * 3 + 2, 12);
  EXPECT_EQ(fem_error(path), path.string() +
                                 ": /elements/connectivity: element 3 has index 12, expected 0 ≤ "
                                 "index < 12 (n_nodes)");

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).set_int("/elements/material_id", 5, 2);
  EXPECT_NE(
      fem_error(path).find("/elements/material_id: element 5 has index 2, expected 0 ≤ index < 2"),
      std::string::npos);

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).set_int("/gauss_points/element", 23, 6);
  EXPECT_NE(fem_error(path).find("/gauss_points/element: Gauss point 23 has index 6, expected 0 ≤ "
                                 "index < 6 (n_elements)"),
            std::string::npos);

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).set_int("/boundary/base/nodes", 0, -1);
  EXPECT_NE(fem_error(path).find("/boundary/base/nodes: entry 0 has index -1"), std::string::npos);

  const fs::path particles = file("particles.h5");
  write_checkpoint(particles, sample_particles(CheckpointKind::particles));
  Damage(particles).set_int("/particles/material_id", 3, -1);
  EXPECT_NE(particle_error(particles).find("/particles/material_id: particle 3 has index -1"),
            std::string::npos);
  write_checkpoint(particles, sample_particles(CheckpointKind::particles));
  Damage(particles).set_int("/particles/element", 2, -2);
  EXPECT_NE(
      particle_error(particles).find("/particles/element: particle 2 has index -2, expected ≥ -1"),
      std::string::npos);
}

TEST_F(Checkpoint, NonPositiveParticleMassOrVolumeIsNamed) {
  const fs::path path = file("particles.h5");
  write_checkpoint(path, sample_particles(CheckpointKind::particles));
  Damage(path).set_double("/particles/mass", 4, 0.0);
  EXPECT_EQ(particle_error(path),
            path.string() + ": /particles/mass: particle 4 has mass 0, expected > 0");
  write_checkpoint(path, sample_particles(CheckpointKind::particles));
  Damage(path).set_double("/particles/volume", 0, -1.0e-3);
  EXPECT_EQ(particle_error(path),
            path.string() + ": /particles/volume: particle 0 has volume -0.001, expected > 0");
}

TEST_F(Checkpoint, MagnitudesNoLandslideReachesAreRefusedOnReading) {
  const fs::path path = file("particles.h5");
  write_checkpoint(path, sample_particles(CheckpointKind::mpm));
  Damage(path).set_double("/particles/strain", 4 * 3 + 1, 4.9e226);
  EXPECT_EQ(particle_error(path),
            path.string() +
                ": /particles/strain: particle 3 has 4.9e+226, beyond ±1e+06 (no landslide "
                "reaches it: damaged data?)");
  write_checkpoint(path, sample_particles(CheckpointKind::mpm));
  Damage(path).set_double("/particles/velocity", 2 * 2, -2.0e5);
  EXPECT_NE(particle_error(path).find("/particles/velocity: particle 2 has -200000 m/s, beyond "
                                      "±100000 m/s"),
            std::string::npos);
  const fs::path fem = file("fem.h5");
  write_checkpoint(fem, sample_fem(ElementType::quad4_2x2));
  Damage(fem).set_double("/gauss_points/stress", 4 * 9, -1.0e27);
  EXPECT_NE(fem_error(fem).find("/gauss_points/stress: Gauss point 9 has -1e+27 Pa, beyond ±1e+13"),
            std::string::npos);
  // The writer refuses the same values, so nothing it writes fails to read back.
  ParticleCheckpoint c = sample_particles(CheckpointKind::mpm);
  c.particles.strain[3][1] = 4.9e226;
  EXPECT_NE(error_of([&] {
              write_checkpoint(file("w.h5"), c);
            }).find("cannot write /particles/strain: particle 3 has 4.9e+226"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(file("w.h5")));
}

TEST_F(Checkpoint, NegativeAccumulatedStrainsRepeatedIdsAndEmptySizesAreRefused) {
  const fs::path path = file("particles.h5");
  write_checkpoint(path, sample_particles(CheckpointKind::mpm));
  Damage(path).set_double("/particles/state/plastic_shear_strain", 2, -0.5);
  EXPECT_EQ(particle_error(path), path.string() +
                                      ": /particles/state/plastic_shear_strain: particle 2 has "
                                      "-0.5, expected ≥ 0");
  write_checkpoint(path, sample_particles(CheckpointKind::mpm));
  Damage(path).set_double("/particles/eps_q", 5, -1e-9);
  EXPECT_NE(particle_error(path).find("/particles/eps_q: particle 5 has -1e-09, expected ≥ 0"),
            std::string::npos);
  write_checkpoint(path, sample_particles(CheckpointKind::mpm));
  Damage(path).set_int("/particles/id", 6, 1000 + 3 * 2);  // particle 2's id
  EXPECT_EQ(
      particle_error(path),
      path.string() + ": /particles/id: particles 2 and 6 share id 1006, expected unique ids");
  write_checkpoint(path, sample_particles(CheckpointKind::mpm));
  Damage(path).set_int("/particles/id", 0, -4);
  EXPECT_EQ(particle_error(path),
            path.string() + ": /particles/id: particle 0 has id -4, expected ≥ 0");
  write_checkpoint(path, sample_particles(CheckpointKind::mpm));
  Damage(path).set_double("/particles/size", 2 * 4 + 1, 0.0);
  EXPECT_NE(particle_error(path).find("/particles/size: particle 4 has size ("), std::string::npos);
  const fs::path fem = file("fem.h5");
  write_checkpoint(fem, sample_fem(ElementType::quad4_2x2));
  Damage(fem).set_double("/gauss_points/weight", 7, 0.0);
  EXPECT_NE(fem_error(fem).find("/gauss_points/weight: Gauss point 7 has weight 0, expected > 0"),
            std::string::npos);
}

/// The byte offset of the first occurrence of the 8 bytes of `value` in `bytes`.
std::size_t offset_of(const std::string& bytes, double value) {
  std::string pattern(sizeof value, '\0');
  std::memcpy(pattern.data(), &value, sizeof value);
  return bytes.find(pattern);
}

TEST_F(Checkpoint, ADamagedDataByteIsReportedByItsChecksum) {
  // A value that occurs once, in /particles/volume (row 5), flipped in its last bit on
  // disk: without the checksum it would read as a slightly different volume.
  const fs::path path = file("particles.h5");
  const ParticleCheckpoint c = sample_particles(CheckpointKind::mpm);
  write_checkpoint(path, c);
  std::string bytes = bytes_of(path);
  const std::size_t at = offset_of(bytes, c.particles.volume[5]);
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(offset_of(bytes.substr(at + 1), c.particles.volume[5]), std::string::npos);
  bytes[at] = static_cast<char>(bytes[at] ^ 1);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  const std::string message = particle_error(path);
  EXPECT_NE(message.find("/particles/volume"), std::string::npos) << message;
  EXPECT_NE(message.find("Fletcher32"), std::string::npos) << message;
}

TEST_F(Checkpoint, StringsAreWrittenFixedLengthAndNothingGoesToTheGlobalHeap) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (const auto& [object, name] :
       {std::pair{"/", "kind"}, std::pair{"/materials/0", "name"},
        std::pair{"/nodes/coordinates", "units"}, std::pair{"/solver", "stage"}}) {
    const hid_t attribute = H5Aopen_by_name(f, object, name, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(attribute, 0) << object << " " << name;
    const hid_t type = H5Aget_type(attribute);
    EXPECT_EQ(H5Tget_class(type), H5T_STRING);
    EXPECT_EQ(H5Tis_variable_str(type), 0) << object << " " << name;
    EXPECT_EQ(H5Tget_cset(type), H5T_CSET_UTF8);
    H5Tclose(type);
    H5Aclose(attribute);
  }
  H5Fclose(f);
  // No global heap collection ("GCOL" signature) anywhere in the file.
  EXPECT_EQ(bytes_of(path).find("GCOL"), std::string::npos);
}

TEST_F(Checkpoint, InconsistentElementTypeAndInadmissibleMaterialAreRejected) {
  const fs::path path = file("fem.h5");
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).set_string_attribute("/elements/connectivity", "type", "tri3");
  EXPECT_NE(fem_error(path).find("/elements/connectivity: attribute type is \"tri3\""),
            std::string::npos);

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).set_string_attribute("/materials/0", "model", "cam-clay");
  EXPECT_NE(fem_error(path).find("/materials/0: attribute model"), std::string::npos);

  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  Damage(path).delete_link("/materials/0");
  EXPECT_NE(fem_error(path).find("/materials: expected groups 0…0 (one per material), found \"1\""),
            std::string::npos);
}

// ---------------------------------------------------------------------------------------
// Failed writes

TEST_F(Checkpoint, WriterFailingHalfWayLeavesTheExistingFileByteIdentical) {
  const fs::path path = file("fem_t2.000.h5");
  write_checkpoint(path, sample_fem(ElementType::quad4_2x2));
  const std::string before = bytes_of(path);

  // The stress is written after the nodes and elements: the writer fails half way.
  FemCheckpoint broken = sample_fem(ElementType::quad4_2x2);
  broken.header.time = 4.0;
  broken.stress[9].y() = std::numeric_limits<double>::quiet_NaN();
  const std::string message = error_of([&] { write_checkpoint(path, broken); });
  EXPECT_EQ(message, path.string() +
                         ": cannot write /gauss_points/stress: Gauss point 9 is not finite (nan)");
  EXPECT_EQ(bytes_of(path), before);

  // A field of the wrong length, found after the nodes were written.
  FemCheckpoint short_field = sample_fem(ElementType::quad4_2x2);
  short_field.volume.pop_back();
  EXPECT_NE(error_of([&] {
              write_checkpoint(path, short_field);
            }).find("cannot write /elements/volume: 5 entries, expected 6 (one per element)"),
            std::string::npos);
  EXPECT_EQ(bytes_of(path), before);

  ParticleCheckpoint light = sample_particles(CheckpointKind::particles);
  light.particles.mass[3] = -1.0;
  EXPECT_NE(error_of([&] {
              write_checkpoint(path, light);
            }).find("cannot write /particles/mass: particle 3 has mass -1, expected > 0"),
            std::string::npos);
  EXPECT_EQ(bytes_of(path), before);

  // No temporary file is left behind and the old checkpoint still reads.
  EXPECT_EQ(std::distance(fs::directory_iterator(folder_), fs::directory_iterator()), 1);
  EXPECT_EQ(read_fem_checkpoint(path).header.time, 2.0);
}

TEST_F(Checkpoint, InconsistentCheckpointsAreNotWritten) {
  const fs::path path = file("x.h5");
  ParticleCheckpoint no_kind = sample_particles(CheckpointKind::mpm);
  no_kind.header.kind = CheckpointKind::fem;
  EXPECT_NE(error_of([&] { write_checkpoint(path, no_kind); }).find("header kind"),
            std::string::npos);

  FemCheckpoint fem = sample_fem(ElementType::tri3);
  fem.boundary_conditions.pop_back();
  EXPECT_NE(error_of([&] { write_checkpoint(path, fem); }).find("3 boundary conditions for 4"),
            std::string::npos);

  fem = sample_fem(ElementType::tri3);
  fem.materials[0].density = -1.0;
  EXPECT_NE(error_of([&] {
              write_checkpoint(path, fem);
            }).find("cannot write /materials/0: density = -1 is not admissible"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace slide
