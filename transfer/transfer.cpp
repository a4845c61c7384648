#include "transfer/transfer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <utility>

#include "common/base/error.hpp"
#include "common/base/numeric.hpp"
#include "common/base/program.hpp"
#include "common/geometry/mesh.hpp"
#include "transfer/pore_water.hpp"
#include "transfer/rbf_interpolation.hpp"

namespace slide::transfer {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// ---------------------------------------------------------------- Gauss-point fields
//
// Every Gauss-point field is interpolated as one block of columns, so a single RBF
// factorisation serves all of them: [σxx σyy σzz σxy | εxx εyy εzz γxy | plastic
// strains | and, when the FE models have surface state, the frozen peak strength and the
// multi-yield surface stresses, 4 per surface]. εq is not a column: it is recomputed
// from the transferred strain, which keeps it consistent with that strain and
// non-negative (an interpolated εq can undershoot).
constexpr Eigen::Index stress_column = 0;
constexpr Eigen::Index strain_column = 4;
constexpr Eigen::Index state_column = 8;
constexpr Eigen::Index peak_strength_column = state_column + 2;
constexpr Eigen::Index surface_column = peak_strength_column + 1;
static_assert(sizeof(MaterialState) == 3 * sizeof(double),
              "a new MaterialState field needs its column in pack_gauss_fields/unpack");

MaterialState default_state() {
  return MaterialState{};
}

FieldValues pack_gauss_fields(const FemCheckpoint& fem) {
  const auto n = static_cast<Eigen::Index>(fem.stress.size());
  const auto surfaces = static_cast<Eigen::Index>(fem.surface_stress.per_point);
  FieldValues values(n, surfaces > 0 ? surface_column + 4 * surfaces : peak_strength_column);
  for (Eigen::Index g = 0; g < n; ++g) {
    const auto i = static_cast<std::size_t>(g);
    values.row(g).segment<4>(stress_column) = fem.stress[i].transpose();
    values.row(g).segment<4>(strain_column) = fem.strain[i].transpose();
    const MaterialState state =
        fem.material_state.empty() ? default_state() : fem.material_state[i];
    values(g, state_column + 0) = state.plastic_shear_strain;
    values(g, state_column + 1) = state.plastic_volumetric_strain;
    if (surfaces == 0) continue;
    values(g, peak_strength_column) = state.peak_strength;
    const auto own = fem.surface_stress.of(i);
    for (Eigen::Index k = 0; k < surfaces; ++k) {
      values.row(g).segment<4>(surface_column + 4 * k) =
          own[static_cast<std::size_t>(k)].transpose();
    }
  }
  return values;
}

// ---------------------------------------------------------------- validation

template <typename T>
void check_size(const std::vector<T>& field, std::size_t expected, std::string_view dataset) {
  if (field.size() != expected) {
    throw Error("FE checkpoint: {} has {} entries, expected {}", dataset, field.size(), expected);
  }
}

bool is_finite(double v) {
  return std::isfinite(v);
}
template <typename Derived>
bool is_finite(const Eigen::MatrixBase<Derived>& v) {
  return v.allFinite();
}
bool is_finite(const MaterialState& s) {
  return std::isfinite(s.plastic_shear_strain) && std::isfinite(s.plastic_volumetric_strain) &&
         std::isfinite(s.peak_strength);
}

template <typename T>
void check_finite(const std::vector<T>& field, std::string_view dataset) {
  for (std::size_t i = 0; i < field.size(); ++i) {
    if (!is_finite(field[i])) {
      throw Error("FE checkpoint: {} entry {} is not finite (NaN or Inf)", dataset, i);
    }
  }
}

/// Every field the transfer uses has a row per node, element or Gauss point.
void validate_sizes(const FemCheckpoint& fem) {
  const Mesh& mesh = fem.mesh;
  const std::size_t nodes = mesh.nodes.size();
  const auto elements = static_cast<std::size_t>(mesh.element_count());
  const std::size_t gauss = fem.gauss_element.size();
  if (elements == 0) throw Error("FE checkpoint: the mesh has no elements");
  check_size(mesh.connectivity, elements * static_cast<std::size_t>(mesh.nodes_per_element()),
             "/elements/connectivity");
  for (const Index node : mesh.connectivity) {
    if (node < 0 || static_cast<std::size_t>(node) >= nodes) {
      throw Error("FE checkpoint: /elements/connectivity refers to node {} of {}", node, nodes);
    }
  }
  check_size(fem.coordinates, nodes, "/nodes/coordinates");
  check_size(fem.displacement, nodes, "/nodes/displacement");
  check_size(fem.velocity, nodes, "/nodes/velocity");
  if (!fem.pore_pressure.empty()) check_size(fem.pore_pressure, nodes, "/nodes/pore_pressure");
  check_size(fem.volume_reference, elements, "/elements/volume_reference");
  check_size(fem.volume, elements, "/elements/volume");
  check_size(fem.gauss_local_coordinates, gauss, "/gauss_points/local_coordinates");
  check_size(fem.gauss_coordinates, gauss, "/gauss_points/coordinates");
  check_size(fem.stress, gauss, "/gauss_points/stress");
  check_size(fem.strain, gauss, "/gauss_points/strain");
  if (!fem.material_state.empty()) check_size(fem.material_state, gauss, "/gauss_points/state");
}

/// Every element's material exists, with a density the masses can come from.
void validate_materials(const FemCheckpoint& fem) {
  for (std::size_t e = 0; e < fem.mesh.material_id.size(); ++e) {
    const auto id = fem.mesh.material_id[e];
    if (id < 0 || static_cast<std::size_t>(id) >= fem.materials.size()) {
      throw Error("FE checkpoint: element {} has material {} of {}", e, id, fem.materials.size());
    }
  }
  for (std::size_t m = 0; m < fem.materials.size(); ++m) {
    const double rho = fem.materials[m].density;
    if (!(rho > 0.0) || !std::isfinite(rho)) {
      throw Error("FE checkpoint: /materials/{} density = {} is not admissible (expected > 0)", m,
                  rho);
    }
  }
}

/// Finite values, positive reference volumes, and a positive current volume wherever the
/// element is not inverted: a positive geometry needs a positive V_t^e (the particles
/// take their volume from it); an inverted element's V_t^e is not used (transfer.hpp).
void validate_values(const FemCheckpoint& fem) {
  for (std::size_t e = 0; e < fem.volume_reference.size(); ++e) {
    if (!(fem.volume_reference[e] > 0.0)) {
      throw Error("FE checkpoint: /elements/volume_reference of element {} is {} (expected > 0)", e,
                  fem.volume_reference[e]);
    }
  }
  check_finite(fem.coordinates, "/nodes/coordinates");
  check_finite(fem.displacement, "/nodes/displacement");
  check_finite(fem.velocity, "/nodes/velocity");
  check_finite(fem.pore_pressure, "/nodes/pore_pressure");
  check_finite(fem.volume_reference, "/elements/volume_reference");
  check_finite(fem.volume, "/elements/volume");
  check_finite(fem.gauss_local_coordinates, "/gauss_points/local_coordinates");
  check_finite(fem.gauss_coordinates, "/gauss_points/coordinates");
  check_finite(fem.stress, "/gauss_points/stress");
  check_finite(fem.strain, "/gauss_points/strain");
  check_finite(fem.material_state, "/gauss_points/state");
  const Mesh& mesh = fem.mesh;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const double volume = fem.volume[static_cast<std::size_t>(e)];
    if (!(volume > 0.0) && !is_inverted(mesh.shape(), mesh.element_nodes(e, fem.coordinates))) {
      throw Error(
          "FE checkpoint: /elements/volume of element {} is {} m³/m, but its current nodes are not "
          "inverted (det J > 0 at every corner): the file is inconsistent",
          e, volume);
    }
  }
}

void validate(const FemCheckpoint& fem) {
  if (fem.header.kind != CheckpointKind::fem) {
    throw Error("expected an FE checkpoint (kind \"fem\"), got kind \"{}\"",
                to_string(fem.header.kind));
  }
  validate_sizes(fem);
  validate_materials(fem);
  validate_values(fem);
  // The reference mesh is the one fem-solve meshed: counter-clockwise elements, every node
  // used, node sets in range. An element inverted there is a damaged file, which
  // --allow-inverted (for elements the run inverted) does not cover; fem-solve --restart
  // refuses the same file.
  validate_mesh(fem.mesh, "FE checkpoint (reference mesh)", fem.materials.size());
}

/// Gauss points of each element as offsets into a list sorted by element (stable, so
/// an element's points keep the order of its rule).
struct GaussIndex {
  std::vector<std::size_t> offsets;  // n_elements + 1
  std::vector<std::size_t> points;
};

GaussIndex index_gauss_points(const FemCheckpoint& fem) {
  const auto elements = static_cast<std::size_t>(fem.mesh.element_count());
  GaussIndex index;
  index.offsets.assign(elements + 1, 0);
  for (std::size_t g = 0; g < fem.gauss_element.size(); ++g) {
    const Index e = fem.gauss_element[g];
    if (e < 0 || static_cast<std::size_t>(e) >= elements) {
      throw Error("FE checkpoint: /gauss_points/element entry {} refers to element {} of {}", g, e,
                  elements);
    }
    ++index.offsets[static_cast<std::size_t>(e) + 1];
  }
  for (std::size_t e = 0; e < elements; ++e) {
    if (index.offsets[e + 1] == 0) throw Error("FE checkpoint: element {} has no Gauss point", e);
    index.offsets[e + 1] += index.offsets[e];
  }
  index.points.resize(fem.gauss_element.size());
  std::vector<std::size_t> next(index.offsets.begin(), index.offsets.end() - 1);
  for (std::size_t g = 0; g < fem.gauss_element.size(); ++g) {
    index.points[next[static_cast<std::size_t>(fem.gauss_element[g])]++] = g;
  }
  return index;
}

// The overshoot limiter of the RBF fields. A multiquadric through Gauss points that a
// distorted or folded mesh has brought close together, with different values, swings
// far beyond the data between them: at column-short t = 2 s (20 folded toe elements,
// condition 7e13) particles got |σ| of 2e8 Pa against 7e5 Pa at the Gauss points, and
// MPM blew up in 26 steps. Each component of a particle is therefore kept within the
// range [lo, hi] of the Gauss values of its element and of the elements sharing a node
// with it, widened by (hi − lo)/2 on each side. The widening lets a linear field through
// untouched, boundary particles included: a particle is at most half an element beyond
// its own Gauss point, while the patch spans at least one element of the field's change.
// Collapsed elements (no RBF centres) still count: without them a patch at the edge of a
// collapsed zone would lose its span across the zone and clip a linear field.
// Counts the particles with at least one limited component, and those with a limited
// stress component.
struct LimitedCounts {
  std::size_t any = 0;
  std::size_t stress = 0;
};

/// Per element the range of every column over its patch (the element and every element
/// sharing a node with it): `lo` and `hi`, n_elements × columns.
struct PatchRange {
  Eigen::MatrixXd lo, hi;
};

PatchRange patch_ranges(const Mesh& mesh, const GaussIndex& gauss_index,
                        const FieldValues& gauss_values) {
  const auto elements = static_cast<std::size_t>(mesh.element_count());
  // Node → elements (CSR).
  std::vector<std::size_t> node_offsets(mesh.nodes.size() + 1, 0);
  for (std::size_t e = 0; e < elements; ++e) {
    for (const Index n : mesh.element(static_cast<Index>(e)))
      ++node_offsets[static_cast<std::size_t>(n) + 1];
  }
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) node_offsets[n + 1] += node_offsets[n];
  std::vector<std::size_t> node_elements(node_offsets.back());
  std::vector<std::size_t> fill(node_offsets.begin(), node_offsets.end() - 1);
  for (std::size_t e = 0; e < elements; ++e) {
    for (const Index n : mesh.element(static_cast<Index>(e)))
      node_elements[fill[static_cast<std::size_t>(n)]++] = e;
  }
  // Each element's own range, then the patch's.
  Eigen::MatrixXd own_lo =
      Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(elements), gauss_values.cols(),
                                std::numeric_limits<double>::infinity());
  Eigen::MatrixXd own_hi = -own_lo;
  for (std::size_t e = 0; e < elements; ++e) {
    for (std::size_t k = gauss_index.offsets[e]; k < gauss_index.offsets[e + 1]; ++k) {
      const auto g = static_cast<Eigen::Index>(gauss_index.points[k]);
      const auto row = static_cast<Eigen::Index>(e);
      own_lo.row(row) = own_lo.row(row).cwiseMin(gauss_values.row(g));
      own_hi.row(row) = own_hi.row(row).cwiseMax(gauss_values.row(g));
    }
  }
  PatchRange range{own_lo, own_hi};
  for (std::size_t e = 0; e < elements; ++e) {
    const auto row = static_cast<Eigen::Index>(e);
    for (const Index n : mesh.element(static_cast<Index>(e))) {
      const auto nn = static_cast<std::size_t>(n);
      for (std::size_t k = node_offsets[nn]; k < node_offsets[nn + 1]; ++k) {
        const auto other = static_cast<Eigen::Index>(node_elements[k]);
        range.lo.row(row) = range.lo.row(row).cwiseMin(own_lo.row(other));
        range.hi.row(row) = range.hi.row(row).cwiseMax(own_hi.row(other));
      }
    }
  }
  return range;
}

LimitedCounts limit_overshoot(const FemCheckpoint& fem, const GaussIndex& gauss_index,
                              const FieldValues& gauss_values,
                              std::span<const Index> particle_element, FieldValues& at_particles) {
  const PatchRange range = patch_ranges(fem.mesh, gauss_index, gauss_values);
  const Eigen::MatrixXd& lo = range.lo;
  const Eigen::MatrixXd& hi = range.hi;
  // Rounding-level excursions (a constant column, a linear field at a boundary) are left
  // alone: only an excess beyond 1e-9 of the field's magnitude is an overshoot. The
  // magnitude is the field's (all four stress or strain components together), since
  // round-off scales with it: a σxy that is zero up to round-off of σyy is not clipped.
  Eigen::RowVectorXd tolerance = 1e-9 * gauss_values.cwiseAbs().colwise().maxCoeff();
  for (const Eigen::Index first : {stress_column, strain_column}) {
    tolerance.segment<4>(first).setConstant(tolerance.segment<4>(first).maxCoeff());
  }
  LimitedCounts limited;
  for (Eigen::Index p = 0; p < at_particles.rows(); ++p) {
    const auto row = static_cast<Eigen::Index>(particle_element[static_cast<std::size_t>(p)]);
    bool changed = false, stress_changed = false;
    for (Eigen::Index c = 0; c < gauss_values.cols(); ++c) {
      const double margin = 0.5 * (hi(row, c) - lo(row, c)) + tolerance(c);
      const double bounded =
          std::clamp(at_particles(p, c), lo(row, c) - margin, hi(row, c) + margin);
      if (bounded != at_particles(p, c)) {
        at_particles(p, c) = bounded;
        changed = true;
        stress_changed = stress_changed || (c >= stress_column && c < stress_column + 4);
      }
    }
    limited.any += changed ? 1 : 0;
    limited.stress += stress_changed ? 1 : 0;
  }
  return limited;
}

/// Elements whose current geometry is inverted, by the definition fem-solve counts with
/// (is_inverted, common/geometry/element.hpp: det J ≤ 0 at a corner, which covers the centre, every
/// particle point and V_t^e ≤ 0), and the worst corner of the first of them.
std::vector<Index> find_inverted_elements(const FemCheckpoint& fem, CornerJacobian* first) {
  const Mesh& mesh = fem.mesh;
  const ElementShape shape = mesh.shape();
  std::vector<Index> inverted;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ElementNodes x = mesh.element_nodes(e, fem.coordinates);
    if (!is_inverted(shape, x)) continue;
    if (inverted.empty()) *first = worst_corner(shape, x);
    inverted.push_back(e);
  }
  return inverted;
}

// ---------------------------------------------------------------- FE momentum and energy

/// Lumped nodal masses (lumped_element_mass: row sums of the consistent mass matrix on
/// the reference configuration, as fem-solve lumps them), scaled so each element's
/// shares add up to its checkpoint mass ρ_e V_0^e.
std::vector<double> lumped_nodal_masses(const FemCheckpoint& fem) {
  const Mesh& mesh = fem.mesh;
  std::vector<double> mass(mesh.nodes.size(), 0.0);
  const int npe = mesh.nodes_per_element();
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const ShapeValues share =
        lumped_element_mass(mesh.shape(), mesh.element_nodes(e, mesh.nodes), 1.0);
    double total = 0.0;
    for (int k = 0; k < npe; ++k) total += share[static_cast<std::size_t>(k)];
    const auto ee = static_cast<std::size_t>(e);
    const double element_mass =
        fem.materials[static_cast<std::size_t>(mesh.material_id[ee])].density *
        fem.volume_reference[ee];
    const auto nodes = mesh.element(e);
    for (int k = 0; k < npe; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      // A reference element with a non-positive Jacobian somewhere still gets equal shares.
      const double fraction = total > 0.0 && share[kk] > 0.0 ? share[kk] / total : 1.0 / npe;
      mass[static_cast<std::size_t>(nodes[kk])] += element_mass * fraction;
    }
  }
  return mass;
}

void fe_momentum_and_energy(const FemCheckpoint& fem, TransferReport& report) {
  const std::vector<double> nodal_mass = lumped_nodal_masses(fem);
  for (std::size_t k = 0; k < nodal_mass.size(); ++k) {
    report.momentum_fe_nodal += nodal_mass[k] * fem.velocity[k];
    report.kinetic_energy_fe_nodal += 0.5 * nodal_mass[k] * fem.velocity[k].squaredNorm();
  }
  // docs/method.md §3: KE_FEM = Σ_e ½ m_e |v̄_e|², v̄_e the mean velocity of the element's nodes.
  const Mesh& mesh = fem.mesh;
  CompensatedSum mass, volume;
  for (Index e = 0; e < mesh.element_count(); ++e) {
    const auto ee = static_cast<std::size_t>(e);
    Vec2 mean = Vec2::Zero();
    for (const Index node : mesh.element(e)) mean += fem.velocity[static_cast<std::size_t>(node)];
    mean /= mesh.nodes_per_element();
    const double m = fem.materials[static_cast<std::size_t>(mesh.material_id[ee])].density *
                     fem.volume_reference[ee];
    mass.add(m);
    volume.add(fem.volume[ee]);
    report.momentum_fe_element += m * mean;
    report.kinetic_energy_fe_element += 0.5 * m * mean.squaredNorm();
  }
  report.mass_fe = mass.value();
  report.volume_fe = volume.value();
}

// ---------------------------------------------------------------- interpolation

/// The interpolation's settings with every default resolved: the one place the methods
/// read their parameters from, and what the report and the particle file record.
struct InterpolationSettings {
  StressInterpolation method = StressInterpolation::rbf;
  RbfPolynomial polynomial = RbfPolynomial::none;
  double shape = 0.0;                  ///< c, m
  int neighbours = 0;                  ///< k of rbf-local
  std::size_t dense_memory_limit = 0;  ///< bytes; resolved for rbf only
};

bool uses_rbf(StressInterpolation method) {
  return method != StressInterpolation::element;
}

/// The Gauss points the RBFs interpolate from: those of the uncollapsed elements.
struct RbfCentres {
  std::vector<Vec2> points;
  FieldValues values;
};

/// What the interpolation reads. `values` holds every Gauss point's fields (for the
/// element baseline); the RBFs interpolate `centres`.
struct GaussFieldInputs {
  const FemCheckpoint& fem;
  const GaussIndex& index;
  const FieldValues& values;
  const RbfCentres& centres;
  std::span<const Vec2> particle_coordinates;
  std::span<const std::int64_t> particle_element;
  std::span<const Vec2> particle_xi;
};

struct Interpolated {
  FieldValues at_particles;
  FieldValues at_gauss_points;  // empty for the element baseline
  RbfDiagnostics diagnostics;
};

Interpolated interpolate_dense_rbf(const GaussFieldInputs& in,
                                   const InterpolationSettings& settings) {
  Interpolated out;
  const DenseRbf rbf(in.centres.points, in.centres.values, settings.shape, settings.polynomial,
                     settings.dense_memory_limit);
  out.at_particles = rbf.evaluate(in.particle_coordinates);
  out.at_gauss_points = rbf.evaluate(in.centres.points);
  out.diagnostics = rbf.diagnostics();
  return out;
}

Interpolated interpolate_local(const GaussFieldInputs& in, const InterpolationSettings& settings) {
  Interpolated out;
  const LocalRbfOptions local{settings.shape, settings.polynomial, settings.neighbours};
  out.at_particles = interpolate_local_rbf(in.centres.points, in.centres.values,
                                           in.particle_coordinates, local, &out.diagnostics);
  RbfDiagnostics at_gauss;
  out.at_gauss_points = interpolate_local_rbf(in.centres.points, in.centres.values,
                                              in.centres.points, local, &at_gauss);
  return out;
}

/// The owning element's Gauss point nearest to reference coordinates ξ (the only one for
/// one-point elements); ties go to the first.
std::size_t nearest_own_gauss(const FemCheckpoint& fem, const GaussIndex& index, std::size_t e,
                              const Vec2& xi) {
  std::size_t best = index.points[index.offsets[e]];
  double best_distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = index.offsets[e]; i < index.offsets[e + 1]; ++i) {
    const std::size_t g = index.points[i];
    const double d = (fem.gauss_local_coordinates[g] - xi).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = g;
    }
  }
  return best;
}

/// The baseline: each particle takes the values of its element's nearest Gauss point.
Interpolated nearest_own_gauss_point(const GaussFieldInputs& in) {
  Interpolated out;
  const auto count = static_cast<std::ptrdiff_t>(in.particle_coordinates.size());
  out.at_particles.resize(static_cast<Eigen::Index>(count), in.values.cols());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t p = 0; p < count; ++p) {
    const auto pp = static_cast<std::size_t>(p);
    const auto e = static_cast<std::size_t>(in.particle_element[pp]);
    const std::size_t best = nearest_own_gauss(in.fem, in.index, e, in.particle_xi[pp]);
    out.at_particles.row(static_cast<Eigen::Index>(p)) =
        in.values.row(static_cast<Eigen::Index>(best));
  }
  return out;
}

Interpolated interpolate_gauss_fields(const GaussFieldInputs& in,
                                      const InterpolationSettings& settings) {
  switch (settings.method) {
    case StressInterpolation::rbf:
      return interpolate_dense_rbf(in, settings);
    case StressInterpolation::rbf_local:
      return interpolate_local(in, settings);
    case StressInterpolation::element:
      break;
  }
  return nearest_own_gauss_point(in);
}

void report_residuals(const FieldValues& values, const FieldValues& at_gauss,
                      TransferReport& report) {
  if (at_gauss.size() == 0) return;
  const FieldValues residual = at_gauss - values;
  const auto stress = residual.middleCols(stress_column, 4);
  report.residual_stress_max = stress.cwiseAbs().maxCoeff();
  report.residual_stress_rms = std::sqrt(stress.squaredNorm() / static_cast<double>(stress.size()));
  double relative = 0.0;
  for (Eigen::Index c = 0; c < values.cols(); ++c) {
    const double scale = values.col(c).cwiseAbs().maxCoeff();
    const double worst = residual.col(c).cwiseAbs().maxCoeff();
    if (scale > 0.0) relative = std::max(relative, worst / scale);
  }
  report.residual_relative_max = relative;
}

// ---------------------------------------------------------------- the phases of transfer()

/// The options the command line cannot check alone (a case file may set them too).
void check_options(const TransferOptions& options) {
  if (options.rbf_shape < 0.0 || !std::isfinite(options.rbf_shape)) {
    throw Error("--rbf-shape {} is not admissible (expected > 0 m)", options.rbf_shape);
  }
  if (options.rbf_neighbours < 0) {
    throw Error("--rbf-neighbours {} is not admissible (expected ≥ 1)", options.rbf_neighbours);
  }
  if (!(options.collapsed_volume_ratio >= 0.0 && options.collapsed_volume_ratio <= 1.0)) {
    throw Error("--collapsed-volume-ratio {} is not admissible (expected 0 to 1)",
                options.collapsed_volume_ratio);
  }
}

/// The report's account of what goes in: the model, the layout and the method.
void describe_input(const FemCheckpoint& fem, const ParticleLayout& layout,
                    const TransferOptions& options, TransferReport& report) {
  report.case_name = fem.header.case_name;
  report.time = fem.header.time;
  report.element_type = std::string(to_string(fem.mesh.element_type));
  report.elements = static_cast<std::size_t>(fem.mesh.element_count());
  report.gauss_points = fem.gauss_element.size();
  report.particles_per_element = layout.label;
  report.particle_rule = layout.rule;
  report.stress_interpolation = std::string(to_string(options.stress_interpolation));
}

/// Inverted elements stop the transfer with an error naming the first, unless the user
/// accepts them; returns a flag per element (1: inverted) for the phases after.
std::vector<std::uint8_t> accept_inverted_elements(const FemCheckpoint& fem,
                                                   const TransferOptions& options,
                                                   TransferReport& report) {
  CornerJacobian worst;
  const std::vector<Index> inverted = find_inverted_elements(fem, &worst);
  if (!inverted.empty() && !options.allow_inverted) {
    const auto e = static_cast<std::size_t>(inverted.front());
    const Vec2 xi = reference_corners(fem.mesh.shape())[static_cast<std::size_t>(worst.corner)];
    throw Error(
        "element {} is inverted at t = {} s (det J = {:.3g} at its corner ξ = ({:.3g}, {:.3g}), "
        "scaled Jacobian {:.3g}, V_t = {:.3g} m³/m){}; transfer an earlier checkpoint, or pass "
        "--allow-inverted to transfer it with its reference volume",
        e, fem.header.time, worst.det_jacobian, xi.x(), xi.y(), worst.scaled_jacobian,
        fem.volume[e],
        inverted.size() > 1 ? fmt::format(", and {} more element(s)", inverted.size() - 1)
                            : std::string());
  }
  report.inverted_elements = inverted;
  std::vector<std::uint8_t> is_inverted(report.elements, 0);
  for (const Index e : inverted) is_inverted[static_cast<std::size_t>(e)] = 1;
  return is_inverted;
}

/// The particles of every element with their nodal fields by the element's shape
/// functions, volume, mass, GIMP domain and origin; `particle_xi` gets their reference
/// coordinates (the element baseline picks its Gauss point by them).
void place_particles(const FemCheckpoint& fem, const ParticleLayout& layout,
                     const std::vector<std::uint8_t>& is_inverted, Particles& particles,
                     std::vector<Vec2>& particle_xi) {
  const Mesh& mesh = fem.mesh;
  const ElementShape shape = mesh.shape();
  const auto per_element = static_cast<std::size_t>(layout.count());
  const std::size_t count = is_inverted.size() * per_element;
  particles.resize(count);
  particle_xi.resize(count);
  const int npe = mesh.nodes_per_element();
  const auto elements = static_cast<std::ptrdiff_t>(is_inverted.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t e = 0; e < elements; ++e) {
    const auto ee = static_cast<std::size_t>(e);
    const auto nodes = mesh.element(e);
    const double density = fem.materials[static_cast<std::size_t>(mesh.material_id[ee])].density;
    // V_p from the deformed element, M_p from the undeformed one (docs/method.md §4).
    const double element_volume = is_inverted[ee] ? fem.volume_reference[ee] : fem.volume[ee];
    const double element_mass = density * fem.volume_reference[ee];
    for (std::size_t i = 0; i < per_element; ++i) {
      const std::size_t p = ee * per_element + i;
      const QuadraturePoint& point = layout.points[i];
      const ShapeValues n = shape_functions(shape, point.xi);
      Vec2 x = Vec2::Zero(), u = Vec2::Zero(), v = Vec2::Zero();
      double pore = 0.0;
      for (int k = 0; k < npe; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        const auto node = static_cast<std::size_t>(nodes[kk]);
        x += n[kk] * fem.coordinates[node];
        u += n[kk] * fem.displacement[node];
        v += n[kk] * fem.velocity[node];
        if (!fem.pore_pressure.empty()) pore += n[kk] * fem.pore_pressure[node];
      }
      particles.coordinates[p] = x;
      particles.displacement[p] = u;
      particles.velocity[p] = v;
      particles.pore_pressure[p] = pore;
      particles.volume[p] = element_volume * point.weight;
      particles.mass[p] = element_mass * point.weight;
      // GIMP domain: a square of the particle's volume (docs/method.md §4).
      const double side = std::sqrt(particles.volume[p]);
      particles.size[p] = Vec2(side, side);
      particles.material_id[p] = mesh.material_id[ee];
      particles.element[p] = e;
      particles.id[p] = static_cast<std::int64_t>(p);
      particle_xi[p] = point.xi;
    }
  }
}

/// The RBF centres: collapsed elements give none (transfer.hpp). Only the RBFs need one.
RbfCentres select_centres(const FemCheckpoint& fem, const FieldValues& values,
                          const std::vector<std::uint8_t>& is_inverted,
                          const TransferOptions& options, TransferReport& report) {
  std::vector<std::uint8_t> is_centre_element(report.elements, 1);
  for (std::size_t e = 0; e < report.elements; ++e) {
    if (is_inverted[e] != 0 ||
        fem.volume[e] < options.collapsed_volume_ratio * fem.volume_reference[e]) {
      is_centre_element[e] = 0;
      ++report.collapsed_elements;
    }
  }
  report.collapsed_volume_ratio = options.collapsed_volume_ratio;
  RbfCentres centres;
  std::vector<Eigen::Index> centre_rows;
  for (std::size_t g = 0; g < report.gauss_points; ++g) {
    if (is_centre_element[static_cast<std::size_t>(fem.gauss_element[g])] == 0) continue;
    centres.points.push_back(fem.gauss_coordinates[g]);
    centre_rows.push_back(static_cast<Eigen::Index>(g));
  }
  const bool rbf = uses_rbf(options.stress_interpolation);
  if (rbf && centres.points.empty()) {
    throw Error(
        "all {} elements have collapsed (inverted or V_t/V_0 < {:g}): no Gauss point is left to "
        "interpolate from; lower --collapsed-volume-ratio or use --stress-interpolation element",
        report.elements, options.collapsed_volume_ratio);
  }
  report.excluded_gauss_points = rbf ? report.gauss_points - centres.points.size() : 0;
  centres.values = values(centre_rows, Eigen::all);
  return centres;
}

/// The user's options with their defaults filled in (c from the centres' spacing, k,
/// the polynomial, the memory limit), recorded in the report.
InterpolationSettings resolve_settings(const FemCheckpoint& fem, const RbfCentres& centres,
                                       const TransferOptions& options, TransferReport& report) {
  InterpolationSettings settings;
  settings.method = options.stress_interpolation;
  settings.polynomial = effective_polynomial(options);
  settings.shape = options.rbf_shape > 0.0
                       ? options.rbf_shape
                       : default_shape_parameter(centres.points.empty() ? fem.gauss_coordinates
                                                                        : centres.points);
  settings.neighbours =
      options.rbf_neighbours > 0 ? options.rbf_neighbours : default_rbf_neighbours;
  if (settings.method == StressInterpolation::rbf) {
    settings.dense_memory_limit =
        options.dense_memory_limit > 0 ? options.dense_memory_limit : default_dense_memory_limit();
  }
  const bool rbf = uses_rbf(settings.method);
  report.rbf_polynomial = rbf ? std::string(to_string(settings.polynomial)) : std::string();
  report.rbf_shape = rbf ? settings.shape : 0.0;
  report.rbf_neighbours =
      settings.method == StressInterpolation::rbf_local
          ? static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(settings.neighbours),
                                                   centres.points.size()))
          : 0;
  return settings;
}

/// The Gauss-point fields at the particles, timed, with the fit's diagnostics and
/// residuals in the report and the RBF overshoots limited.
FieldValues fields_at_particles(const GaussFieldInputs& in, const InterpolationSettings& settings,
                                TransferReport& report) {
  const Clock::time_point started = Clock::now();
  Interpolated interpolated = interpolate_gauss_fields(in, settings);
  report.seconds_interpolation = seconds_since(started);
  report.condition_estimate = interpolated.diagnostics.condition_estimate;
  report.factorisations = interpolated.diagnostics.factorisations;
  report.reduced_polynomial = interpolated.diagnostics.reduced_polynomial;
  report_residuals(in.centres.values, interpolated.at_gauss_points, report);
  FieldValues& at = interpolated.at_particles;
  if (uses_rbf(settings.method)) {
    const LimitedCounts limited =
        limit_overshoot(in.fem, in.index, in.values, in.particle_element, at);
    report.limited_particles = limited.any;
    report.limited_stress_particles = limited.stress;
  }
  return std::move(at);
}

/// Stress, strain and plastic state from their columns; εq recomputed from the strain.
void unpack_gauss_fields(const FieldValues& at, Particles& particles, TransferReport& report) {
  for (std::size_t p = 0; p < particles.count(); ++p) {
    const auto row = static_cast<Eigen::Index>(p);
    particles.stress[p] = at.row(row).segment<4>(stress_column).transpose();
    particles.strain[p] = at.row(row).segment<4>(strain_column).transpose();
    particles.eps_q[p] = deviatoric_strain(particles.strain[p]);
    MaterialState& state = particles.state[p];
    state.plastic_shear_strain = at(row, state_column + 0);
    state.plastic_volumetric_strain = at(row, state_column + 1);
    // An accumulated plastic shear strain is never negative; an RBF can undershoot.
    if (state.plastic_shear_strain < 0.0) {
      state.plastic_shear_strain = 0.0;
      ++report.clamped_plastic_strain;
    }
  }
}

/// The multi-yield state, when both phases of a material run the model: its frozen peak
/// strength and its surfaces continue (mpm-solve's switch to its models brings them back
/// onto their limits); any other MPM model starts from the stress alone.
void continue_multi_yield_state(const FemCheckpoint& fem, const FieldValues& at,
                                Particles& particles) {
  const std::size_t count = particles.count();
  particles.surface_stress.per_point = surfaces_needed(fem.materials, Phase::mpm);
  particles.surface_stress.resize(count);
  const auto surfaces = static_cast<Eigen::Index>(fem.surface_stress.per_point);
  if (surfaces == 0 || particles.surface_stress.per_point != fem.surface_stress.per_point) return;
  for (std::size_t p = 0; p < count; ++p) {
    const Material& m = fem.materials[static_cast<std::size_t>(particles.material_id[p])];
    if (m.model_of(Phase::mpm) != m.model) continue;
    const auto row = static_cast<Eigen::Index>(p);
    // A point whose FE model froze no strength stays unfrozen (negative).
    particles.state[p].peak_strength = std::max(at(row, peak_strength_column), -1.0);
    const auto own = particles.surface_stress.of(p);
    for (Eigen::Index k = 0; k < surfaces; ++k) {
      own[static_cast<std::size_t>(k)] = at.row(row).segment<4>(surface_column + 4 * k).transpose();
    }
  }
}

/// The particle file's header and transfer record: where the particles came from and how.
void describe_particle_file(const FemCheckpoint& fem, const ParticleLayout& layout,
                            const TransferReport& report, ParticleCheckpoint& out) {
  out.header = fem.header;
  out.header.kind = CheckpointKind::particles;
  out.header.schema_version = checkpoint_schema_version;
  out.header.producer = fmt::format("fem2mpm ({})", version_string());
  out.materials = fem.materials;
  out.transfer.transfer_time = fem.header.time;
  out.transfer.particles_per_element = layout.label;
  out.transfer.stress_interpolation = report.stress_interpolation;
  // The element baseline fits no polynomial: the report leaves it blank, the file says so.
  out.transfer.rbf_polynomial =
      report.rbf_polynomial.empty() ? std::string("none") : report.rbf_polynomial;
  out.transfer.rbf_shape = report.rbf_shape;
  out.transfer.rbf_neighbours = report.rbf_neighbours;
  // The base motion, so that mpm-solve continues the same earthquake from t_T.
  out.motion = fem.motion;
}

/// The conservation totals of both sides, so the report can show what the transfer kept.
void add_totals(const FemCheckpoint& fem, const Particles& particles, TransferReport& report) {
  fe_momentum_and_energy(fem, report);
  report.particles = particles.count();
  CompensatedSum mass, volume;
  for (std::size_t p = 0; p < particles.count(); ++p) {
    mass.add(particles.mass[p]);
    volume.add(particles.volume[p]);
    report.momentum_particles += particles.mass[p] * particles.velocity[p];
    report.kinetic_energy_particles +=
        0.5 * particles.mass[p] * particles.velocity[p].squaredNorm();
  }
  report.mass_particles = mass.value();
  report.volume_particles = volume.value();
}

/// The materials with the transfer's correlation, and which of them are assumed liquefied;
/// Error for a name that is no material, or one without a liquefaction rule.
std::pair<MaterialTable, std::vector<bool>> liquefaction_settings(const MaterialTable& from,
                                                                  const TransferOptions& options) {
  MaterialTable materials = from;
  std::vector<bool> assumed(materials.size(), false);
  for (const std::string& name : options.assume_liquefied) {
    const auto m = std::ranges::find(materials, name, &Material::name);
    if (m == materials.end()) {
      throw Error("--assume-liquefied {}: no material of that name in the FE checkpoint", name);
    }
    if (!m->liquefaction.enabled) {
      throw Error(
          "--assume-liquefied {}: the material has no liquefaction rule "
          "([materials.liquefaction])",
          name);
    }
    assumed[static_cast<std::size_t>(m - materials.begin())] = true;
  }
  if (options.correlation) {
    for (Material& m : materials) {
      if (!m.liquefaction.enabled) continue;
      m.liquefaction.correlation = *options.correlation;
      if (*options.correlation == ResidualStrengthCorrelation::ratio &&
          std::isnan(m.liquefaction.strength_ratio)) {
        throw Error("--correlation ratio: material \"{}\" gives no strength_ratio", m.name);
      }
      if (std::isnan(m.liquefaction.blow_count) &&
          *options.correlation != ResidualStrengthCorrelation::ratio &&
          *options.correlation != ResidualStrengthCorrelation::none) {
        throw Error("--correlation {}: material \"{}\" gives no blow_count",
                    to_string(*options.correlation), m.name);
      }
    }
  }
  return {std::move(materials), std::move(assumed)};
}

}  // namespace

TransferOptions options_from(const TransferSpec& spec) {
  TransferOptions options;
  options.particles.nx = spec.particles_x;
  options.particles.ny = spec.particles_y;
  options.particles.triangle = spec.particles_triangle;
  options.stress_interpolation = spec.stress_interpolation;
  options.rbf_polynomial = spec.rbf_polynomial;
  options.rbf_shape = spec.rbf_shape;
  options.rbf_neighbours = spec.rbf_neighbours;
  return options;
}

RbfPolynomial effective_polynomial(const TransferOptions& options) {
  if (options.rbf_polynomial) return *options.rbf_polynomial;
  return options.stress_interpolation == StressInterpolation::rbf_local ? RbfPolynomial::linear
                                                                        : RbfPolynomial::none;
}

std::size_t default_dense_memory_limit() {
  constexpr std::size_t cap = std::size_t{16} << 30;
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::size_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit) {
    if (key == "MemAvailable:") return std::min(cap, kib * 1024 / 4 * 3);
  }
  return std::size_t{4} << 30;  // no /proc/meminfo: a modest guess
}

TransferResult transfer(const FemCheckpoint& fem, const TransferOptions& options,
                        const Logger* logger) {
  const Clock::time_point started = Clock::now();
  validate(fem);
  const GaussIndex gauss_index = index_gauss_points(fem);
  const ParticleLayout layout = make_layout(fem.mesh.shape(), options.particles);
  check_options(options);

  TransferResult result;
  TransferReport& report = result.report;
  describe_input(fem, layout, options, report);
  const std::vector<std::uint8_t> is_inverted = accept_inverted_elements(fem, options, report);
  Particles& particles = result.particles.particles;
  std::vector<Vec2> particle_xi;
  place_particles(fem, layout, is_inverted, particles, particle_xi);

  const FieldValues values = pack_gauss_fields(fem);
  const RbfCentres centres = select_centres(fem, values, is_inverted, options, report);
  const InterpolationSettings settings = resolve_settings(fem, centres, options, report);
  if (logger != nullptr) {
    logger->info("{} elements ({}), {} Gauss points -> {} particles; interpolating by {}",
                 report.elements, report.element_type, report.gauss_points, particles.count(),
                 report.stress_interpolation);
  }
  const GaussFieldInputs inputs{
      fem, gauss_index, values, centres, particles.coordinates, particles.element, particle_xi};
  const FieldValues at = fields_at_particles(inputs, settings, report);
  unpack_gauss_fields(at, particles, report);
  continue_multi_yield_state(fem, at, particles);
  if (!fem.static_pore_pressure.empty()) {
    std::vector<std::size_t> source(particles.count());
    for (std::size_t p = 0; p < source.size(); ++p) {
      source[p] = nearest_own_gauss(fem, gauss_index,
                                    static_cast<std::size_t>(particles.element[p]), particle_xi[p]);
    }
    const auto [materials, assumed] = liquefaction_settings(fem.materials, options);
    carry_pore_water(fem, materials, assumed, particle_xi, source, particles, report.pore_water);
    result.particles.materials = materials;
  }

  const MaterialTable kept = result.particles.materials;
  describe_particle_file(fem, layout, report, result.particles);
  if (!kept.empty()) result.particles.materials = kept;  // with the transfer's overrides
  add_totals(fem, particles, report);
  report.seconds_total = seconds_since(started);
  return result;
}

}  // namespace slide::transfer
