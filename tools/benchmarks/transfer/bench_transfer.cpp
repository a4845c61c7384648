// Benchmarks of the transfer (not timed tests; transfer/README.md quotes the figures).
//
//   bench_transfer neighbours           accuracy and time of rbf-local against k, with the
//                                       dense rbf for reference: the measurement behind
//                                       the default k
//   bench_transfer scale [ELEMENTS]     ELEMENTS (default 100000) one-point quads × 16
//                                       particles with rbf-local: wall time and peak memory
//   bench_transfer dense N_G            the dense rbf on N_G one-point quads: time and peak
//                                       memory (run one size per process)
//   bench_transfer write-fem ELEMENTS OUT.h5
//                                       the FE state of `scale` as a checkpoint, to time
//                                       fem2mpm end to end (reading and writing included)
//   bench_transfer geostatic OUT.csv    the geostatic-4x4 σyy error of every particle
//                                       (plot_geostatic_error.py draws it)
//
// The FE state is built in memory: a block of one-point quads under a smooth
// displacement, carrying a geostatic stress plus a smooth non-linear perturbation (what
// a collapsing column's stress looks like a few seconds in: not linear, varying over a
// few elements).
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <string>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/io/checkpoint.hpp"
#include "tools/synthetic/fem_checkpoints.hpp"
#include "transfer/rbf_interpolation.hpp"
#include "transfer/transfer.hpp"

namespace {

using namespace slide;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Peak resident memory of this process so far (VmHWM), in MiB.
double peak_memory_mib() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kib = 0.0;
      status >> kib;
      return kib / 1024.0;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0.0;
}

constexpr double density = 1700.0;

/// Geostatic stress of a column of height `height` plus a smooth perturbation with a
/// wavelength of `wavelength` metres and 20 % of ρgH amplitude.
Vec4 smooth_stress(const Vec2& x, double height, double wavelength) {
  const double rho_g_h = density * gravity_acceleration * height;
  const double k = 2.0 * 3.141592653589793 / wavelength;
  const double wave = 0.2 * rho_g_h * std::sin(k * x.x() + 0.3) * std::cos(0.7 * k * x.y());
  const double syy = -density * gravity_acceleration * (height - x.y());
  return {0.3 * syy + wave, syy - 0.5 * wave, 0.3 * syy, 0.25 * wave};
}

FemCheckpoint smooth_block(int nx, int ny, double h, double wavelength) {
  synthetic::BlockFields fields;
  fields.displacement = synthetic::distortion(0.1 * h);
  const double height = ny * h;
  fields.stress = [=](const Vec2& x) { return smooth_stress(x, height, wavelength); };
  fields.velocity = [](const Vec2& x) { return Vec2(0.5 + 0.01 * x.y(), -0.02 * x.x()); };
  return synthetic::make_block(nx, ny, nx * h, height, ElementType::quad4_1gp, fields, density);
}

struct StressError {
  double max = 0.0;  // over every particle
  double rms = 0.0;
  double interior = 0.0;  // over the particles at least one element from the boundary
};

/// Stress error at the particles over ρgH, against the exact field or a reference.
StressError stress_error(const Particles& particles, double height, double wavelength, double h,
                         double width, const Particles* reference = nullptr) {
  const double rho_g_h = density * gravity_acceleration * height;
  StressError error;
  double sum = 0.0;
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const Vec2& x = particles.coordinates[p];
    const Vec4 exact =
        reference != nullptr ? reference->stress[p] : smooth_stress(x, height, wavelength);
    const double e = (particles.stress[p] - exact).cwiseAbs().maxCoeff() / rho_g_h;
    error.max = std::max(error.max, e);
    sum += e * e;
    // Reference positions of the block: undo nothing, the distortion is 0.1 h at most.
    const Vec2 X = x - particles.displacement[p];
    if (X.x() > h && X.x() < width - h && X.y() > h && X.y() < height - h) {
      error.interior = std::max(error.interior, e);
    }
  }
  error.rms = std::sqrt(sum / static_cast<double>(particles.count()));
  return error;
}

void neighbours() {
  // 60 × 40 one-point quads of 1 m (2400 Gauss points, 38400 particles): small enough
  // for the dense reference, a perturbation wavelength of 12 elements.
  const int nx = 60, ny = 40;
  const double h = 1.0, wavelength = 12.0, width = nx * h, height = ny * h;
  const FemCheckpoint fem = smooth_block(nx, ny, h, wavelength);
  fmt::print(
      "rbf-local accuracy against k: {} one-point quads, 4x4 particles, smooth field "
      "(wavelength {} elements); errors over rho g H; 'vs dense' compares with the "
      "dense rbf of the same polynomial\n",
      fem.mesh.element_count(), wavelength / h);
  fmt::print("{:>10} {:>4} {:>10} {:>10} {:>10} {:>10} {:>10} {:>7} {:>10}\n", "method", "k", "max",
             "interior", "rms", "vs dense", "vs dense i", "time s", "condition");
  std::map<RbfPolynomial, Particles> dense_result;
  auto row = [&](const transfer::TransferOptions& options, const std::string& label) {
    const Clock::time_point start = Clock::now();
    const transfer::TransferResult result = transfer::transfer(fem, options);
    const double seconds = seconds_since(start);
    const Particles& particles = result.particles.particles;
    const StressError error = stress_error(particles, height, wavelength, h, width);
    const RbfPolynomial polynomial = transfer::effective_polynomial(options);
    if (options.stress_interpolation == StressInterpolation::rbf)
      dense_result[polynomial] = particles;
    const StressError versus =
        stress_error(particles, height, wavelength, h, width, &dense_result.at(polynomial));
    fmt::print(
        "{:>10} {:>4} {:>10.2e} {:>10.2e} {:>10.2e} {:>10.2e} {:>10.2e} {:>7.3f} {:>10.2e}\n",
        label, options.rbf_neighbours > 0 ? fmt::format("{}", options.rbf_neighbours) : "-",
        error.max, error.interior, error.rms, versus.max, versus.interior, seconds,
        result.report.condition_estimate);
  };
  for (auto polynomial : {RbfPolynomial::none, RbfPolynomial::linear}) {
    transfer::TransferOptions dense;
    dense.stress_interpolation = StressInterpolation::rbf;
    dense.rbf_polynomial = polynomial;
    row(dense, fmt::format("rbf+{}", polynomial == RbfPolynomial::linear ? "lin" : "none"));
  }
  for (int k : {4, 6, 8, 10, 12, 16, 20, 24, 32, 48, 64}) {
    for (auto polynomial : {RbfPolynomial::none, RbfPolynomial::linear}) {
      transfer::TransferOptions local;
      local.stress_interpolation = StressInterpolation::rbf_local;
      local.rbf_polynomial = polynomial;
      local.rbf_neighbours = k;
      row(local, fmt::format("local+{}", polynomial == RbfPolynomial::linear ? "lin" : "none"));
    }
  }
}

void scale(int elements) {
  // A 2.5:1 block of 0.25 m one-point quads.
  const int ny = std::max(1, static_cast<int>(std::lround(std::sqrt(elements / 2.5))));
  const int nx = std::max(1, elements / ny);
  const double h = 0.25;
  const Clock::time_point built = Clock::now();
  const FemCheckpoint fem = smooth_block(nx, ny, h, 24.0 * h);
  const double build_seconds = seconds_since(built);
  transfer::TransferOptions options;
  options.stress_interpolation = StressInterpolation::rbf_local;
  const Clock::time_point start = Clock::now();
  const transfer::TransferResult result = transfer::transfer(fem, options);
  const double seconds = seconds_since(start);
  const StressError error = stress_error(result.particles.particles, ny * h, 24.0 * h, h, nx * h);
  fmt::print(
      "scale: {} x {} = {} one-point quads, {} particles, rbf-local k = {} + linear\n"
      "  transfer wall time {:.2f} s (interpolation {:.2f} s, {} factorisations), FE state "
      "built in {:.2f} s\n"
      "  peak memory (VmHWM, whole process incl. the FE state) {:.0f} MiB\n"
      "  stress error over rho g H: max {:.2e}, interior {:.2e}, rms {:.2e}\n",
      nx, ny, fem.mesh.element_count(), result.report.particles, result.report.rbf_neighbours,
      seconds, result.report.seconds_interpolation, result.report.factorisations, build_seconds,
      peak_memory_mib(), error.max, error.interior, error.rms);
}

void dense(int gauss_points) {
  const int ny = std::max(1, static_cast<int>(std::lround(std::sqrt(gauss_points / 2.5))));
  const int nx = std::max(1, gauss_points / ny);
  const FemCheckpoint fem = smooth_block(nx, ny, 1.0, 12.0);
  // Particle positions from the element baseline (cheap), then the dense RBF by hand so
  // that the factorisation and the evaluation are timed apart.
  transfer::TransferOptions options;
  options.stress_interpolation = StressInterpolation::element;
  const Particles particles = transfer::transfer(fem, options).particles.particles;
  transfer::FieldValues values(static_cast<Eigen::Index>(fem.stress.size()), 10);
  for (std::size_t g = 0; g < fem.stress.size(); ++g) {
    const auto r = static_cast<Eigen::Index>(g);
    values.row(r).head<4>() = fem.stress[g].transpose();
    values.row(r).segment<4>(4) = fem.strain[g].transpose();
    values(r, 8) = values(r, 9) = 0.0;
  }
  const double c = transfer::default_shape_parameter(fem.gauss_coordinates);
  const Clock::time_point start = Clock::now();
  const transfer::DenseRbf rbf(fem.gauss_coordinates, values, c, RbfPolynomial::none,
                               transfer::default_dense_memory_limit());
  const double fit_seconds = seconds_since(start);
  const Clock::time_point evaluated = Clock::now();
  const transfer::FieldValues at = rbf.evaluate(particles.coordinates);
  const double evaluate_seconds = seconds_since(evaluated);
  fmt::print(
      "dense: N_g = {}: factorisation + solve {:.2f} s, evaluation at {} particles {:.2f} s, "
      "matrix {:.0f} MiB, peak memory {:.0f} MiB, condition {:.2e} (check {:.3g})\n",
      fem.gauss_element.size(), fit_seconds, particles.count(), evaluate_seconds,
      static_cast<double>(
          transfer::dense_rbf_bytes(fem.gauss_element.size(), RbfPolynomial::none)) /
          (1 << 20),
      peak_memory_mib(), rbf.diagnostics().condition_estimate, at(0, 1));
}

/// The geostatic-4x4 check as a table for plotting: one row per particle with its
/// position and the σyy error over ρgH of the plain multiquadric (rbf, default c).
void geostatic(const std::string& csv) {
  const double height = 4.0;
  synthetic::BlockFields fields;
  fields.stress = synthetic::geostatic_stress(density, 0.23, height);
  const FemCheckpoint fem =
      synthetic::make_block(16, 16, 4.0, height, ElementType::quad4_1gp, fields, density);
  const transfer::TransferResult result = transfer::transfer(fem, transfer::TransferOptions{});
  const Particles& particles = result.particles.particles;
  std::ofstream out(csv);
  out << "x,y,error_over_rho_g_h\n";
  const double rho_g_h = density * gravity_acceleration * height;
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const Vec2& x = particles.coordinates[p];
    const double exact = -density * gravity_acceleration * (height - x.y());
    out << fmt::format("{},{},{}\n", x.x(), x.y(), (particles.stress[p][1] - exact) / rho_g_h);
  }
  if (!out) throw Error("{}: write failed", csv);
  fmt::print("wrote {} ({} particles)\n", csv, particles.count());
}

/// Writes the FE state of `scale` as a checkpoint, for timing fem2mpm end to end.
void write_fem(int elements, const std::string& path) {
  const int ny = std::max(1, static_cast<int>(std::lround(std::sqrt(elements / 2.5))));
  const int nx = std::max(1, elements / ny);
  write_checkpoint(path, smooth_block(nx, ny, 0.25, 6.0));
  fmt::print("wrote {} ({} one-point quads)\n", path, nx * ny);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "neighbours") {
      neighbours();
    } else if (mode == "scale") {
      scale(argc > 2 ? std::stoi(argv[2]) : 100000);
    } else if (mode == "write-fem" && argc > 3) {
      write_fem(std::stoi(argv[2]), argv[3]);
    } else if (mode == "geostatic" && argc > 2) {
      geostatic(argv[2]);
    } else if (mode == "dense" && argc > 2) {
      dense(std::stoi(argv[2]));
    } else {
      fmt::print(stderr,
                 "usage: bench_transfer neighbours | scale [ELEMENTS] | dense N_G | geostatic "
                 "OUT.csv | write-fem ELEMENTS OUT.h5\n");
      return 2;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_transfer: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
