#include "fem/fem_output.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/program.hpp"

namespace slide::fem {

std::string checkpoint_file_name(double time) {
  return fmt::format("fem_t{:.3f}.h5", time);
}

FemCheckpoint make_checkpoint(const FemModel& model, const FemState& state,
                              const CheckpointContext& context) {
  const std::vector<Vec2> x = current_coordinates(model, state);
  const ElementQuality quality = evaluate_quality(model, state, x);
  FemCheckpoint checkpoint;
  checkpoint.header.kind = CheckpointKind::fem;
  checkpoint.header.producer = "fem-solve (" + version_string() + ")";
  checkpoint.header.time = state.time;
  checkpoint.header.step = state.step;
  checkpoint.header.case_name = context.case_name;
  checkpoint.header.pe0 = context.pe0;
  checkpoint.mesh = model.mesh;
  checkpoint.boundary_conditions = context.boundary_conditions;
  checkpoint.friction_coefficient = context.friction_coefficient;

  checkpoint.coordinates = x;
  checkpoint.displacement = state.displacement;
  checkpoint.velocity = state.velocity;
  checkpoint.acceleration = state.acceleration;
  checkpoint.pore_pressure.assign(x.size(), 0.0);  // dry analyses

  checkpoint.jacobian_ratio = quality.jacobian_ratio;
  checkpoint.scaled_jacobian = quality.scaled_jacobian;
  checkpoint.volume_reference = model.volume_reference;
  checkpoint.volume = quality.volume;
  checkpoint.hourglass_force = state.hourglass_force;

  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element);
  const auto n_points = state.stress.size();
  checkpoint.gauss_element.resize(n_points);
  checkpoint.gauss_local_coordinates.resize(n_points);
  checkpoint.gauss_coordinates.resize(n_points);
  checkpoint.gauss_weight.resize(n_points);
  for (std::size_t gp = 0; gp < n_points; ++gp) {
    const auto e = static_cast<Index>(gp / n_gauss);
    const std::size_t p = gp % n_gauss;
    checkpoint.gauss_element[gp] = e;
    checkpoint.gauss_local_coordinates[gp] = model.gauss_local[p];
    checkpoint.gauss_coordinates[gp] =
        map_to_physical(model.mesh.shape(), model.mesh.element_nodes(e, x), model.gauss_local[p]);
    checkpoint.gauss_weight[gp] = model.gauss_rule_weight[p];
  }
  checkpoint.stress = state.stress;
  checkpoint.strain = state.strain;
  checkpoint.eps_q = quality.gauss_eps_q;
  checkpoint.state = state.material_state;
  checkpoint.surface_stress = state.surface_stress;
  checkpoint.materials = model.materials;
  checkpoint.solver = context.solver;
  return checkpoint;
}

FemState state_from_checkpoint(const FemModel& model, const FemCheckpoint& checkpoint,
                               const std::filesystem::path& file) {
  const auto require_size = [&](std::size_t size, Index expected, std::string_view name) {
    if (size != static_cast<std::size_t>(expected)) {
      throw Error("{}: {} has {} entries, expected {} for this mesh", file.string(), name, size,
                  expected);
    }
  };
  require_size(checkpoint.displacement.size(), model.node_count(), "/nodes/displacement");
  require_size(checkpoint.velocity.size(), model.node_count(), "/nodes/velocity");
  require_size(checkpoint.acceleration.size(), model.node_count(), "/nodes/acceleration");
  require_size(checkpoint.stress.size(), model.gauss_count(), "/gauss_points/stress");
  require_size(checkpoint.strain.size(), model.gauss_count(), "/gauss_points/strain");
  require_size(checkpoint.state.size(), model.gauss_count(), "/gauss_points/state");
  if (model.hourglass) {
    require_size(checkpoint.hourglass_force.size(), model.element_count(),
                 "the hourglass forces of the quad4-1gp elements");
  }
  FemState state;
  state.time = checkpoint.header.time;
  state.step = checkpoint.header.step;
  state.displacement = checkpoint.displacement;
  state.velocity = checkpoint.velocity;
  state.acceleration = checkpoint.acceleration;
  state.stress = checkpoint.stress;
  state.strain = checkpoint.strain;
  state.material_state = checkpoint.state;
  // The surfaces the case's failure-stage models need: those of the file when it has
  // as many per point, else none yet (a geostatic checkpoint, or a model changed since:
  // the switch then sets them up from the stress).
  state.surface_stress.per_point = surfaces_needed(model.materials, Phase::fem);
  if (checkpoint.surface_stress.per_point == state.surface_stress.per_point) {
    state.surface_stress = checkpoint.surface_stress;
  } else {
    state.surface_stress.resize(state.stress.size());
  }
  state.yielded.assign(state.stress.size(), 0);
  if (model.hourglass) state.hourglass_force = checkpoint.hourglass_force;

  const auto finite = [](const auto& values) {
    for (const auto& v : values) {
      if (!v.allFinite()) return false;
    }
    return true;
  };
  if (!finite(state.displacement) || !finite(state.velocity) || !finite(state.stress) ||
      !finite(state.strain) || !finite(state.hourglass_force) || !std::isfinite(state.time)) {
    throw Error("{}: the checkpoint holds non-finite values (NaN or Inf)", file.string());
  }
  return state;
}

bool HistoryRow::inside_zone() const {
  if (std::isnan(jacobian_ratio_avg) || std::isnan(eps_q_avg)) return true;
  return jacobian_ratio_avg >= zone_jacobian_ratio_avg_min && eps_q_avg <= zone_eps_q_avg_max;
}

bool HistoryRow::inverted() const {
  if (std::isnan(scaled_jacobian_min)) return jacobian_ratio_min < 0.0;
  return scaled_jacobian_min < 0.0;  // is_inverted: a folded corner (a flat one is not)
}

namespace {

std::string format_row(const HistoryRow& row) {
  return fmt::format(
      "{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{},{:.10g},{:.10g},{:.10g}"
      "\n",
      row.time, row.kinetic_energy, row.pe0, row.ke_over_pe0, row.jacobian_ratio_min,
      row.jacobian_ratio_avg, row.eps_q_avg, row.eps_q_max, row.n_elements_yielding, row.area_ratio,
      row.scaled_jacobian_min, row.scaled_jacobian_avg);
}

/// One row of `columns` numbers (12, or 9 for a history without the shape columns, which
/// then come back NaN).
bool parse_row(const std::string& line, std::size_t columns, HistoryRow& row) {
  std::array<double, 12> values{};
  values.fill(std::numeric_limits<double>::quiet_NaN());
  const char* cursor = line.c_str();
  for (std::size_t i = 0; i < columns; ++i) {
    char* end = nullptr;
    values[i] = std::strtod(cursor, &end);
    if (end == cursor) return false;
    cursor = end;
    if (i + 1 < columns) {
      if (*cursor != ',') return false;
      ++cursor;
    }
  }
  row = {values[0], values[1],  values[2],
         values[3], values[4],  values[5],
         values[6], values[7],  static_cast<Index>(values[8]),
         values[9], values[10], values[11]};
  return true;
}

}  // namespace

void HistoryFile::resume(double time, const Logger& logger) {
  rows_.clear();
  std::ifstream in(path_);
  if (!in) {
    logger.warning("{}: not found; the history restarts at t = {:.3f} s", path_.string(), time);
    return;
  }
  std::string line;
  std::size_t columns = 0;
  if (std::getline(in, line)) {
    if (line == history_header) columns = 12;
    if (line == history_header_without_shape) columns = 9;
  }
  if (columns == 0) {
    logger.warning("{}: not a fem-solve history; it is replaced", path_.string());
    return;
  }
  while (std::getline(in, line)) {
    HistoryRow row;
    if (!parse_row(line, columns, row)) break;
    if (row.time > time + 1e-9) break;
    rows_.push_back(row);
  }
}

void HistoryFile::add(const HistoryRow& row) {
  rows_.push_back(row);
  write();
}

void HistoryFile::write() const {
  std::string text = std::string(history_header) + "\n";
  for (const auto& row : rows_) text += format_row(row);
  write_text_atomically(path_, text);
}

VtkSeries::VtkSeries(const std::filesystem::path& output_dir)
    : folder_(output_dir / "vtk"),
      mesh_series_(output_dir / "fem.pvd"),
      gauss_series_(output_dir / "fem_gauss_points.pvd") {}

void VtkSeries::resume(double time) {
  mesh_series_.resume(time);
  gauss_series_.resume(time);
}

void VtkSeries::write(const FemModel& model, const FemState& state,
                      std::span<const Vec2> coordinates, const ElementQuality& quality) {
  const auto n_elements = static_cast<std::size_t>(model.element_count());
  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element);
  std::vector<Vec4> stress(n_elements, Vec4::Zero()), strain(n_elements, Vec4::Zero());
  std::vector<double> material(n_elements), yielded(n_elements), plastic(n_elements, 0.0);
  std::vector<double> gauss_plastic(state.stress.size()), gauss_yielded(state.stress.size());
  std::vector<double> gauss_element(state.stress.size());
  std::vector<Vec2> gauss_x(state.stress.size());
  for (std::size_t e = 0; e < n_elements; ++e) {
    const ElementNodes x = model.mesh.element_nodes(static_cast<Index>(e), coordinates);
    for (std::size_t p = 0; p < n_gauss; ++p) {
      const std::size_t gp = e * n_gauss + p;
      stress[e] += state.stress[gp] / static_cast<double>(n_gauss);
      strain[e] += state.strain[gp] / static_cast<double>(n_gauss);
      plastic[e] += state.material_state[gp].plastic_shear_strain / static_cast<double>(n_gauss);
      gauss_plastic[gp] = state.material_state[gp].plastic_shear_strain;
      gauss_yielded[gp] = state.yielded[gp];
      gauss_element[gp] = static_cast<double>(e);
      gauss_x[gp] = map_to_physical(model.mesh.shape(), x, model.gauss_local[p]);
    }
    material[e] = model.mesh.material_id[e];
    yielded[e] = quality.yielded[e];
  }
  const std::string stem = fmt::format("{:06d}", state.step);
  const auto mesh_file = folder_ / ("fem_" + stem + ".vtu");
  write_vtk_mesh(mesh_file, coordinates, model.mesh.shape(), model.mesh.connectivity,
                 {vtk_field("displacement", std::span<const Vec2>(state.displacement)),
                  vtk_field("velocity", std::span<const Vec2>(state.velocity))},
                 {vtk_field("stress", std::span<const Vec4>(stress)),
                  vtk_field("strain", std::span<const Vec4>(strain)),
                  vtk_field("eps_q", std::span<const double>(quality.eps_q)),
                  vtk_field("jacobian_ratio", std::span<const double>(quality.jacobian_ratio)),
                  vtk_field("scaled_jacobian", std::span<const double>(quality.scaled_jacobian)),
                  vtk_field("plastic_shear_strain", std::span<const double>(plastic)),
                  vtk_field("material_id", std::span<const double>(material)),
                  vtk_field("yielded", std::span<const double>(yielded))});
  mesh_series_.add(state.time, std::filesystem::path("vtk") / mesh_file.filename());
  const auto gauss_file = folder_ / ("fem_gauss_points_" + stem + ".vtu");
  write_vtk_points(gauss_file, gauss_x,
                   {vtk_field("stress", std::span<const Vec4>(state.stress)),
                    vtk_field("strain", std::span<const Vec4>(state.strain)),
                    vtk_field("eps_q", std::span<const double>(quality.gauss_eps_q)),
                    vtk_field("plastic_shear_strain", std::span<const double>(gauss_plastic)),
                    vtk_field("yielded", std::span<const double>(gauss_yielded)),
                    vtk_field("element", std::span<const double>(gauss_element))});
  gauss_series_.add(state.time, std::filesystem::path("vtk") / gauss_file.filename());
}

}  // namespace slide::fem
