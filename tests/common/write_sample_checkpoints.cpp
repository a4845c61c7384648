// Writes one small checkpoint of each kind (fem.h5, particles.h5, mpm.h5) into the folder
// given on the command line, for read_checkpoint_with_h5py.py to read with h5py. The
// values follow simple formulas that the Python script checks:
//
//   mesh        2×1 quad4-2x2 elements on [0, 2]×[0, 1], nodes numbered row by row
//   node k      X = (k mod 3, k div 3), u = (0.01 k, −0.02 k), v = (k, 0), p_w = 1000 k
//   point g     stress = (−1000 (g+1), −2000 (g+1), −1500 (g+1), 100 g) Pa
//               eps_q = 0.001 g, plastic_shear_strain = 0.01 g
//   particles   one per Gauss point, mass = ρ V with V = 0.25 m³/m, id = 100 + g
//
// Usage: write_sample_checkpoints FOLDER
#include <cstdio>
#include <exception>
#include <filesystem>

#include "common/io/checkpoint.hpp"
#include "tools/synthetic/soil.hpp"

namespace slide {
namespace {

MaterialTable sample_materials() {
  Material soil =
      synthetic::material("soil", MaterialModel::mohr_coulomb, 2000.0, 1.0e7, 0.3, 30.0, 5000.0);
  soil.tension_cutoff = 0.0;
  return {soil, synthetic::material("rock", MaterialModel::linear_elastic, 2600.0, 5.0e9, 0.25)};
}

FemCheckpoint sample_fem() {
  FemCheckpoint c;
  c.header = {CheckpointKind::fem,
              checkpoint_schema_version,
              "write_sample_checkpoints",
              2.0,
              40,
              "h5py-sample",
              1.5e6};
  Mesh& mesh = c.mesh;
  mesh.element_type = ElementType::quad4_2x2;
  for (int k = 0; k < 6; ++k) {
    const double kd = k;
    mesh.nodes.emplace_back(static_cast<double>(k % 3), static_cast<double>(k / 3));
    c.displacement.emplace_back(0.01 * kd, -0.02 * kd);
    c.coordinates.push_back(mesh.nodes.back() + c.displacement.back());
    c.velocity.emplace_back(kd, 0.0);
    c.acceleration.push_back(Vec2::Zero());
    c.pore_pressure.push_back(1000.0 * kd);
  }
  mesh.connectivity = {0, 1, 4, 3, 1, 2, 5, 4};
  mesh.material_id = {0, 1};
  mesh.node_sets = {{"left", {0, 3}, Vec2(-1.0, 0.0)},
                    {"right", {2, 5}, Vec2(1.0, 0.0)},
                    {"base", {0, 1, 2}, Vec2(0.0, -1.0)}};
  c.boundary_conditions = {BoundaryCondition::roller, BoundaryCondition::roller,
                           BoundaryCondition::friction};
  c.friction_coefficient = 0.4;
  c.jacobian_ratio = {1.0, 0.9};
  for (Index e = 0; e < mesh.element_count(); ++e) {
    c.scaled_jacobian.push_back(
        scaled_jacobian(mesh.shape(), mesh.element_nodes(e, c.coordinates)));
  }
  c.volume_reference = {1.0, 1.0};
  c.volume = {1.0, 0.9};

  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ElementNodes x = mesh.element_nodes(e, c.coordinates);
    for (const auto& point : quadrature_rule(mesh.element_type)) {
      const double g = static_cast<double>(c.gauss_element.size());
      c.gauss_element.push_back(e);
      c.gauss_local_coordinates.push_back(point.xi);
      c.gauss_coordinates.push_back(map_to_physical(mesh.shape(), x, point.xi));
      c.gauss_weight.push_back(point.weight);
      c.stress.emplace_back(-1000.0 * (g + 1), -2000.0 * (g + 1), -1500.0 * (g + 1), 100.0 * g);
      c.strain.emplace_back(1.0e-4 * g, -2.0e-4 * g, 0.0, 5.0e-5 * g);
      c.eps_q.push_back(0.001 * g);
      c.material_state.push_back({0.01 * g, 0.0});
    }
  }
  c.materials = sample_materials();
  c.solver = {
      {"stage", std::string("failure")}, {"time_step", 1.0e-3}, {"steps", std::int64_t{40}}};
  return c;
}

/// One particle at each Gauss point of the FE sample, as fem2mpm with 2x2 would place them.
ParticleCheckpoint sample_particles(const FemCheckpoint& fem) {
  ParticleCheckpoint c;
  c.header = fem.header;
  c.header.kind = CheckpointKind::particles;
  c.header.step = 0;
  const std::size_t n = fem.gauss_element.size();
  Particles& p = c.particles;
  p.resize(n);
  for (std::size_t g = 0; g < n; ++g) {
    const auto e = static_cast<std::size_t>(fem.gauss_element[g]);
    p.coordinates[g] = fem.gauss_coordinates[g];
    p.stress[g] = fem.stress[g];
    p.strain[g] = fem.strain[g];
    p.eps_q[g] = fem.eps_q[g];
    p.volume[g] = 0.25;
    p.material_id[g] = fem.mesh.material_id[e];
    p.mass[g] = fem.materials[static_cast<std::size_t>(p.material_id[g])].density * p.volume[g];
    p.size[g] = Vec2(0.5, 0.5);
    p.element[g] = fem.gauss_element[g];
    p.id[g] = static_cast<std::int64_t>(100 + g);
    p.state[g] = fem.material_state[g];
  }
  c.materials = fem.materials;
  c.transfer = {2.0, "2x2", "rbf", "linear", 0.5, 0};
  return c;
}

/// The particles one second later, moved 0.1 m to the right, as mpm-solve would write them.
ParticleCheckpoint sample_mpm(ParticleCheckpoint c) {
  c.header.kind = CheckpointKind::mpm;
  c.header.producer = "write_sample_checkpoints";
  c.header.time = 3.0;
  c.header.step = 500;
  for (std::size_t i = 0; i < c.particles.count(); ++i) {
    c.particles.coordinates[i].x() += 0.1;
    c.particles.displacement[i] = Vec2(0.1, 0.0);
    c.particles.velocity[i] = Vec2(0.1, 0.0);
  }
  // An APIC run: the affine velocity of a rigid rotation ω = 0.2 rad/s about the origin,
  // C = [[0, −ω], [ω, 0]].
  const double omega = 0.2;
  c.particles.affine_velocity.assign(c.particles.count(), Vec4(0.0, -omega, omega, 0.0));
  c.solver = {{"grid_spacing", 0.5}, {"shape_function", std::string("gimp")}};
  return c;
}

}  // namespace
}  // namespace slide

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_sample_checkpoints FOLDER\n");
    return 2;
  }
  try {
    const std::filesystem::path folder = argv[1];
    const slide::FemCheckpoint fem = slide::sample_fem();
    const slide::ParticleCheckpoint particles = slide::sample_particles(fem);
    slide::write_checkpoint(folder / "fem.h5", fem);
    slide::write_checkpoint(folder / "particles.h5", particles);
    slide::write_checkpoint(folder / "mpm.h5", slide::sample_mpm(particles));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "write_sample_checkpoints: error: %s\n", error.what());
    return 1;
  }
  return 0;
}
