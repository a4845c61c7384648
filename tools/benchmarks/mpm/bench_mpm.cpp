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
//
// In the MPI build, under mpirun, the solver runs on the ranks (docs/parallel.md,
// "Scaling"): each rank uses the listed threads, the wall time is the slowest rank's, and
// it also prints per step and rank the bytes sent and the time in the exchanges (halo
// sums, migration, re-cuts, waits for the neighbours). --widen K makes the column and the
// grid K times as long, K times the particles: the weak-scaling run on K ranks.
//
//   mpirun -np 2 build-mpi/tools/benchmarks/mpm/bench_mpm --threads 1 --skip 200
//   tools/benchmarks/mpm/scaling.sh       (1 → 2 ranks, strong and weak, with ratios)
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>
#include <omp.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
#include "common/base/ranks.hpp"
#include "mpm/domain.hpp"
#include "mpm/mpm_solver.hpp"
#include "mpm/particle_generation.hpp"
#include "tools/benchmarks/digest.hpp"
#include "tools/benchmarks/instruction_counter.hpp"
#include "tools/synthetic/soil.hpp"

namespace {

using namespace slide;
using namespace slide::mpm;

/// column-short's soil without a tension cut-off.
Material column_soil() {
  return synthetic::material("soil", MaterialModel::mohr_coulomb, 1700.0, 23.8e6, 0.23, 22.2,
                             1000.0);
}

MpmSolver make_column(ShapeFunction shape, UpdateScheme scheme, VelocityTransfer transfer,
                      double pic_fraction, VolumetricSmoothing smoothing, int sort_interval,
                      int widen, const Ranks& ranks) {
  MpmSpec spec;
  spec.domain_min = Vec2(0, 0);
  spec.domain_max = Vec2(200.0 * widen, 45);
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
  Particles p =
      generate_box_particles(settings.grid, Vec2(0, 0), Vec2(50.0 * widen, 40), 4, 4, materials, 0);
  apply_k0_stresses(p, materials, std::vector<double>(p.count(), 40.0));
  keep_part(p, 0, ranks);  // on several ranks, each starts from its part (distribute)
  MpmSolver solver(settings, materials, std::move(p));
  solver.return_to_yield_surface();
  return solver;
}

}  // namespace

namespace {

/// The per-message costs of the weak-scaling model (docs/parallel.md): the mean time of
/// one all-reduce of a double and of one exchange of a halo band (`bytes`) with both
/// neighbours, over `repeat` of each, in µs.
std::pair<double, double> message_costs(const Ranks& ranks, std::size_t bytes, int repeat) {
  using clock = std::chrono::steady_clock;
  const std::vector<std::byte> band(bytes, std::byte{1});
  const int rank = ranks.rank(), last = ranks.size() - 1;
  double sink = 0.0;
  ranks.barrier();
  auto begin = clock::now();
  for (int i = 0; i < repeat; ++i) sink += ranks.sum(1.0);
  const double reduce = std::chrono::duration<double>(clock::now() - begin).count();
  ranks.barrier();
  begin = clock::now();
  for (int i = 0; i < repeat; ++i) {
    sink += static_cast<double>(
        ranks.exchange(rank < last ? rank + 1 : -1, band, rank > 0 ? rank - 1 : -1).size());
    sink += static_cast<double>(
        ranks.exchange(rank > 0 ? rank - 1 : -1, band, rank < last ? rank + 1 : -1).size());
  }
  const double exchange = std::chrono::duration<double>(clock::now() - begin).count();
  if (sink < 0) std::puts("");  // keeps the loops
  return {ranks.max(reduce) / repeat * 1e6, ranks.max(exchange) / repeat * 1e6};
}

/// Per rank of one timed run, gathered on the root.
struct RankFigures {
  double exchange_seconds = 0.0;
  double bytes_sent = 0.0;
  double particles = 0.0;
};

/// The command line. The defaults are those of the runout cases: uGIMP, MUSL, APIC, cell
/// smoothing.
struct Options {
  int steps = 500, repeat = 3, sort_interval = 10, skip = 0, widen = 1;
  double pic_fraction = 0.0;
  std::string threads = "1,2", shape = "gimp", scheme = "musl", transfer = "apic",
              smoothing = "cell";

  void add_to(CLI::App& app) {
    app.add_option("--steps", steps, "timed steps per run");
    app.add_option("--repeat", repeat, "runs per thread count (the best is reported)");
    app.add_option("--threads", threads, "comma-separated thread counts");
    app.add_option("--shape", shape, "gimp or linear");
    app.add_option("--scheme", scheme, "musl or usl");
    app.add_option("--transfer", transfer, "grid-to-particle velocity transfer: flip-pic or apic")
        ->check(CLI::IsMember({"flip-pic", "apic"}));
    app.add_option("--pic-fraction", pic_fraction, "PIC share of flip-pic (0: pure FLIP)");
    app.add_option("--smoothing", smoothing, "volumetric smoothing: none or cell")
        ->check(CLI::IsMember({"none", "cell"}));
    app.add_option("--sort-interval", sort_interval, "steps between two sorts by cell");
    app.add_option("--skip", skip, "untimed steps before timing");
    app.add_option("--widen", widen, "column and grid this many times as long (weak scaling)")
        ->check(CLI::PositiveNumber);
  }
  MpmSolver column(const Ranks& ranks) const {
    return make_column(shape == "linear" ? ShapeFunction::linear : ShapeFunction::gimp,
                       scheme == "usl" ? UpdateScheme::usl : UpdateScheme::musl,
                       transfer == "apic" ? VelocityTransfer::apic : VelocityTransfer::flip_pic,
                       pic_fraction,
                       smoothing == "cell" ? VolumetricSmoothing::cell : VolumetricSmoothing::none,
                       sort_interval, widen, ranks);
  }
  std::vector<int> thread_counts() const {
    std::vector<int> counts;
    std::stringstream list(threads);
    for (std::string item; std::getline(list, item, ',');) counts.push_back(std::stoi(item));
    return counts;
  }
};

/// The bits of the particles' evolving fields, in particle order (one rank).
std::uint64_t particle_digest(const Particles& p) {
  return bench::digest(p.coordinates, p.displacement, p.velocity, p.stress, p.strain, p.eps_q,
                       p.pore_pressure, p.volume, p.affine_velocity, p.state, p.id);
}

/// The best of `repeat` timed runs on the current thread count.
struct Best {
  double rate = 0.0, wall = 0.0;
  std::optional<double> instructions;  ///< of the timed steps (1 thread, with a counter)
  std::size_t particles = 0;
  MpmSolver::Memory memory;
  std::vector<RankFigures> figures;
  std::uint64_t digest = 0;  ///< of the last run's particles
};

Best time_runs(const Options& o, const Ranks& ranks, int threads) {
  Best best;
  bench::InstructionCounter counter;
  for (int r = 0; r < o.repeat; ++r) {
    MpmSolver solver = o.column(ranks);
    solver.distribute(ranks);
    const double dt = solver.courant_time_step(0.5);
    for (int s = 0; s < o.skip; ++s) solver.step(dt);
    const Subdomain* domain = solver.subdomain();
    const double exchanged_before = domain ? domain->exchange_seconds : 0.0;
    const auto sent_before = domain ? domain->bytes_sent : 0;
    ranks.barrier();
    const auto begin = std::chrono::steady_clock::now();
    counter.start();
    for (int s = 0; s < o.steps; ++s) solver.step(dt);
    const std::optional<double> instructions = counter.stop();
    const double wall =
        ranks.max(std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
    best.particles =
        static_cast<std::size_t>(ranks.sum(static_cast<double>(solver.active_count())));
    if (best.particles == 0) {
      throw Error(
          "no particle is left on the grid after {} steps: this variant is unstable "
          "on column-short",
          o.skip + o.steps);
    }
    const double rate = static_cast<double>(best.particles) * static_cast<double>(o.steps) / wall;
    if (rate > best.rate) {
      best.rate = rate;
      best.wall = wall;
      if (threads == 1 && !ranks.distributed()) best.instructions = instructions;
      const RankFigures mine{domain ? domain->exchange_seconds - exchanged_before : 0.0,
                             domain ? static_cast<double>(domain->bytes_sent - sent_before) : 0.0,
                             static_cast<double>(solver.active_count())};
      best.figures = Ranks::values_of<RankFigures>(
          ranks.gather_to_root(Ranks::bytes_of(std::span<const RankFigures>(&mine, 1))));
    }
    best.memory = solver.memory();
    best.digest = particle_digest(solver.particles());
  }
  return best;
}

/// The lines of one thread count: the rate, per rank the exchanges, the memory.
std::string report(const Best& best, int threads, double rate_one, const Options& o,
                   const Ranks& ranks) {
  const double n = static_cast<double>(best.particles);
  auto per = [n](std::size_t bytes) { return static_cast<double>(bytes) / n; };
  std::string text = fmt::format(
      "{}threads={} particles={} particle_steps_per_s={:.4g} wall_per_step_ms={:.4g}{}\n",
      ranks.distributed() ? fmt::format("ranks={} ", ranks.size()) : "", threads, best.particles,
      best.rate, 1e3 * best.wall / o.steps,
      threads > 1 && rate_one > 0 ? fmt::format(" speedup={:.2f}", best.rate / rate_one) : "");
  // Per rank and step: the halo and migration traffic and the time it took.
  for (std::size_t r = 0; ranks.distributed() && r < best.figures.size(); ++r) {
    const RankFigures& f = best.figures[r];
    text += fmt::format(
        "  rank {}: particles={:.0f} exchange_ms_per_step={:.4g} ({:.1f} % of the step) "
        "kB_sent_per_step={:.4g}\n",
        r, f.particles, 1e3 * f.exchange_seconds / o.steps, 100 * f.exchange_seconds / best.wall,
        f.bytes_sent / 1e3 / o.steps);
  }
  if (threads == 1 && !ranks.distributed()) {
    text += best.instructions ? fmt::format("  instructions_per_particle_step={:.0f}\n",
                                            *best.instructions / (n * static_cast<double>(o.steps)))
                              : "  instructions_per_particle_step: no hardware counter here "
                                "(tools/benchmarks/instructions.sh counts them under callgrind)\n";
  }
  // Equal digests: bit-identical particles (tools/benchmarks/digest.hpp).
  if (!ranks.distributed()) text += fmt::format("  digest={:016x}\n", best.digest);
  // The windows keep their widest capacity, so this is the peak of the steps run.
  if (!ranks.distributed()) {
    const MpmSolver::Memory& m = best.memory;
    text += fmt::format(
        "  bytes/particle: arrays {:.0f} + sort peak {:.0f} + grid/windows {:.0f} = {:.0f}\n",
        per(m.particle_arrays), per(m.sort_peak), per(m.grid), per(m.total()));
  }
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  prefer_yielding_threads(argv);  // as mpm-solve runs
  const RankSession session(argc, argv);
  const Ranks& ranks = Ranks::world();
  CLI::App app{"bench_mpm: particle-steps per second of the MPM step loop (column-short)"};
  Options o;
  o.add_to(app);
  CLI11_PARSE(app, argc, argv);
  // An unstable variant (e.g. --shape linear with APIC here) ends with the one-line error.
  return run_main_on_ranks("bench_mpm", [&] {
    const std::string transfer_name =
        o.transfer == "apic" ? o.transfer
                             : fmt::format("{} (PIC share {})", o.transfer, o.pic_fraction);
    // Only the root prints (the other ranks' figures reach it through gather_to_root).
    auto print = [&](const std::string& line) {
      if (ranks.root()) std::fputs(line.c_str(), stdout);
    };
    print(fmt::format(
        "bench_mpm: column-short{}, {}, {}, {}, smoothing {}, sort every {} steps, {} timed steps "
        "(after {}){}\n",
        o.widen > 1 ? fmt::format(" widened ×{}", o.widen) : "", o.shape, o.scheme, transfer_name,
        o.smoothing, o.sort_interval, o.steps, o.skip,
        ranks.distributed() ? fmt::format(", {} ranks", ranks.size()) : ""));
    if (ranks.distributed()) {
      // A halo band of column-short: 3 node columns × 48 rows of NodeSums (5 doubles).
      const auto [reduce_us, exchange_us] = message_costs(ranks, 3 * 48 * 40, 2000);
      print(
          fmt::format("messages: allreduce_us={:.3g} halo_exchange_8kB_both_neighbours_us={:.3g}\n",
                      reduce_us, exchange_us));
    }
    double rate_one = 0.0;
    for (int t : o.thread_counts()) {
      omp_set_num_threads(t);
      const Best best = time_runs(o, ranks, t);
      if (t == 1) rate_one = best.rate;
      print(report(best, t, rate_one, o, ranks));
    }
  });
}
