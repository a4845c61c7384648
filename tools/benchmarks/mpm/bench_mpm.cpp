// Benchmark of the MPM step loop on the column-short case (docs/method.md §7): the 50 m × 40 m
// column of frictional soil (Mohr–Coulomb, ρ 1700, E 23.8 MPa, ν 0.23, φ 22.2°, c 1 kPa),
// 4 × 4 particles per 1 m cell (32,000 particles), K0 stresses, on a 200 m × 45 m grid
// with roller walls and a frictional base (μ = 0.466), released at t = 0. It times N
// steps of the real solver (no output) on 1 and on 2 threads and prints particle-steps
// per second, the best of R repetitions, and the memory per particle.
//
//   build/tools/benchmarks/mpm/bench_mpm [--steps 500] [--repeat 3] [--threads 1,2]
//                                  [--shape gimp|linear] [--scheme musl|usl]
//                                  [--transfer flip-pic|apic] [--pic-fraction 0]
//                                  [--sort-interval 10] [--skip 0]
//
// --skip S first runs S untimed steps (the column has started to collapse and particles
// move between cells, which is when the sort cadence matters).
#include <chrono>
#include <cstdio>
#include <sstream>

#include <CLI/CLI.hpp>
#include <omp.h>

#include "mpm/mpm_solver.hpp"
#include "mpm/particle_generation.hpp"

namespace {

using namespace slide;
using namespace slide::mpm;

Material column_soil() {
  Material m;
  m.name = "soil";
  m.model = MaterialModel::mohr_coulomb;
  m.density = 1700.0;
  m.youngs_modulus = 23.8e6;
  m.poisson_ratio = 0.23;
  m.friction_angle = 22.2;
  m.cohesion = 1000.0;
  return m;
}

MpmSolver make_column(ShapeFunction shape, UpdateScheme scheme, VelocityTransfer transfer,
                      double pic_fraction, VolumetricSmoothing smoothing, int sort_interval) {
  MpmSpec spec;
  spec.domain_min = Vec2(0, 0);
  spec.domain_max = Vec2(200, 45);
  spec.cell_size = 1.0;
  spec.shape_function = shape;
  spec.update_scheme = scheme;
  spec.velocity_transfer = transfer;
  spec.pic_fraction = pic_fraction;
  spec.volumetric_smoothing = smoothing;
  spec.boundaries = {{"left", BoundaryCondition::roller},
                     {"right", BoundaryCondition::roller},
                     {"base", BoundaryCondition::friction},
                     {"top", BoundaryCondition::free}};
  spec.friction_coefficient = 0.466;
  MpmSettings settings = MpmSettings::from(spec);
  settings.sort_interval = sort_interval;
  const MaterialTable materials{column_soil()};
  Particles p = generate_box_particles(settings.grid, Vec2(0, 0), Vec2(50, 40), 4, 4, materials, 0);
  apply_k0_stresses(p, materials, std::vector<double>(p.count(), 40.0));
  MpmSolver solver(settings, materials, std::move(p));
  solver.return_to_yield_surface();
  return solver;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_mpm: particle-steps per second of the MPM step loop (column-short)"};
  int steps = 500, repeat = 3, sort_interval = 10, skip = 0;
  double pic_fraction = 0.0;
  // The defaults are those of the runout cases: uGIMP, MUSL, APIC, cell smoothing.
  std::string threads_list = "1,2", shape = "gimp", scheme = "musl", transfer = "apic",
              smoothing = "cell";
  app.add_option("--steps", steps, "timed steps per run");
  app.add_option("--repeat", repeat, "runs per thread count (the best is reported)");
  app.add_option("--threads", threads_list, "comma-separated thread counts");
  app.add_option("--shape", shape, "gimp or linear");
  app.add_option("--scheme", scheme, "musl or usl");
  app.add_option("--transfer", transfer, "grid-to-particle velocity transfer: flip-pic or apic")
      ->check(CLI::IsMember({"flip-pic", "apic"}));
  app.add_option("--pic-fraction", pic_fraction, "PIC share of flip-pic (0: pure FLIP)");
  app.add_option("--smoothing", smoothing, "volumetric smoothing: none or cell")
      ->check(CLI::IsMember({"none", "cell"}));
  app.add_option("--sort-interval", sort_interval, "steps between two sorts by cell");
  app.add_option("--skip", skip, "untimed steps before timing");
  CLI11_PARSE(app, argc, argv);
  const ShapeFunction shape_function =
      shape == "linear" ? ShapeFunction::linear : ShapeFunction::gimp;
  const UpdateScheme update_scheme = scheme == "usl" ? UpdateScheme::usl : UpdateScheme::musl;
  const VelocityTransfer velocity_transfer =
      transfer == "apic" ? VelocityTransfer::apic : VelocityTransfer::flip_pic;
  const VolumetricSmoothing volumetric_smoothing =
      smoothing == "cell" ? VolumetricSmoothing::cell : VolumetricSmoothing::none;

  std::vector<int> threads;
  std::stringstream list(threads_list);
  for (std::string item; std::getline(list, item, ',');) threads.push_back(std::stoi(item));

  const std::string transfer_name =
      transfer == "apic" ? transfer : fmt::format("{} (PIC share {})", transfer, pic_fraction);
  std::printf(
      "bench_mpm: column-short, %s, %s, %s, smoothing %s, sort every %d steps, %d timed steps "
      "(after %d)\n",
      shape.c_str(), scheme.c_str(), transfer_name.c_str(), smoothing.c_str(), sort_interval, steps,
      skip);
  double rate_one = 0.0;
  for (int t : threads) {
    omp_set_num_threads(t);
    double best = 0.0;
    std::size_t particles = 0;
    MpmSolver::Memory memory;
    for (int r = 0; r < repeat; ++r) {
      MpmSolver solver = make_column(shape_function, update_scheme, velocity_transfer, pic_fraction,
                                     volumetric_smoothing, sort_interval);
      const double dt = solver.courant_time_step(0.5);
      for (int s = 0; s < skip; ++s) solver.step(dt);
      const auto begin = std::chrono::steady_clock::now();
      for (int s = 0; s < steps; ++s) solver.step(dt);
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
      particles = solver.active_count();
      best = std::max(best, static_cast<double>(particles) * static_cast<double>(steps) / wall);
      memory = solver.memory();
    }
    if (t == 1) rate_one = best;
    const double n = static_cast<double>(particles);
    auto per = [n](std::size_t bytes) { return static_cast<double>(bytes) / n; };
    std::printf(
        "threads=%d particles=%zu particle_steps_per_s=%.4g%s\n", t, particles, best,
        t > 1 && rate_one > 0 ? fmt::format(" speedup={:.2f}", best / rate_one).c_str() : "");
    // The windows keep their widest capacity, so this is the peak of the steps run.
    std::printf("  bytes/particle: arrays %.0f + sort peak %.0f + grid/windows %.0f = %.0f\n",
                per(memory.particle_arrays), per(memory.sort_peak), per(memory.grid),
                per(memory.total()));
  }
}
