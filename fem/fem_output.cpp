#include "fem/fem_output.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
#include "common/io/atomic_file.hpp"
#include "fem/pore_fluid.hpp"

namespace slide::fem {

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

  static_cast<FeFields&>(checkpoint) = state;
  checkpoint.coordinates = x;
  checkpoint.jacobian_ratio = quality.jacobian_ratio;
  checkpoint.scaled_jacobian = quality.scaled_jacobian;
  checkpoint.volume_reference = model.elements.volume_reference;
  checkpoint.volume = quality.volume;

  const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
  const auto n_points = state.stress.size();
  checkpoint.gauss_element.resize(n_points);
  checkpoint.gauss_local_coordinates.resize(n_points);
  checkpoint.gauss_coordinates.resize(n_points);
  checkpoint.gauss_weight.resize(n_points);
  for (std::size_t gp = 0; gp < n_points; ++gp) {
    const auto e = static_cast<Index>(gp / n_gauss);
    const std::size_t p = gp % n_gauss;
    checkpoint.gauss_element[gp] = e;
    checkpoint.gauss_local_coordinates[gp] = model.rule.local[p];
    checkpoint.gauss_coordinates[gp] =
        map_to_physical(model.mesh.shape(), model.mesh.element_nodes(e, x), model.rule.local[p]);
    checkpoint.gauss_weight[gp] = model.rule.weight[p];
  }
  checkpoint.eps_q = quality.gauss_eps_q;
  checkpoint.materials = model.materials;
  checkpoint.solver = context.solver;
  return checkpoint;
}

namespace {

/// A checkpoint's pore water for `model`: refused without its references when the case is
/// saturated; none for a dry case; the elements' p of a file written before elements
/// carried it taken from the nodes (element_pressure_from_nodes).
void restore_pore_water(const FemModel& model, const std::filesystem::path& file, FemState& state) {
  if (!model.fluid.active()) {
    state.element_pore_pressure.clear();
    return;
  }
  if (state.static_pore_pressure.empty() || state.initial_vertical_effective_stress.empty()) {
    throw Error(
        "{}: has no /nodes/static_pore_pressure or /gauss_points/"
        "initial_vertical_effective_stress: it was written without pore water, and this case "
        "has [fem.water]",
        file.string());
  }
  if (state.element_pore_pressure.empty()) {
    state.element_pore_pressure = element_pressure_from_nodes(model, state.pore_pressure);
  }
}

}  // namespace

FemState state_from_checkpoint(const FemModel& model, const FemCheckpoint& checkpoint,
                               const std::filesystem::path& file) {
  const auto require_rows = [&](RowKind kind, Index expected, std::string_view group) {
    const auto rows = static_cast<std::size_t>(expected);
    if (const auto name = field_of_wrong_size(fe_fields, checkpoint, kind, rows)) {
      throw Error("{}: /{}/{} does not have {} rows, as this mesh", file.string(), group, *name,
                  rows);
    }
  };
  require_rows(RowKind::node, model.node_count(), "nodes");
  require_rows(RowKind::gauss_point, model.gauss_count(), "gauss_points");
  if (model.hourglass &&
      checkpoint.hourglass_force.size() != static_cast<std::size_t>(model.element_count())) {
    throw Error(
        "{}: /elements/hourglass_force does not have {} rows: the quad4-1gp elements "
        "need their hourglass forces",
        file.string(), model.element_count());
  }
  FemState state;
  static_cast<FeFields&>(state) = checkpoint;
  state.time = checkpoint.header.time;
  state.step = checkpoint.header.step;
  // The surfaces the case's failure-stage models need: those of the file when it has
  // as many per point, else none yet (a geostatic checkpoint, or a model changed since:
  // the switch then sets them up from the stress).
  const std::size_t surfaces = surfaces_needed(model.materials, Phase::fem);
  if (state.surface_stress.per_point != surfaces) {
    state.surface_stress = SurfaceStresses{surfaces, {}};
    state.surface_stress.resize(state.stress.size());
  }
  if (!model.hourglass) state.hourglass_force.clear();
  restore_pore_water(model, file, state);
  state.yielded.assign(state.stress.size(), 0);
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

std::vector<double> values_of(const HistoryRow& r, bool water) {
  std::vector<double> values{
      r.time,        r.kinetic_energy,      r.pe0,
      r.ke_over_pe0, r.jacobian_ratio_min,  r.jacobian_ratio_avg,
      r.eps_q_avg,   r.eps_q_max,           static_cast<double>(r.n_elements_yielding),
      r.area_ratio,  r.scaled_jacobian_min, r.scaled_jacobian_avg};
  if (water) {
    values.push_back(r.pore_pressure_ratio_max);
    values.push_back(r.high_pore_pressure_area);
  }
  return values;
}

HistoryRow row_of(const std::vector<double>& v) {
  HistoryRow row{v[0], v[1],  v[2], v[3], v[4], v[5], v[6], v[7], static_cast<Index>(v[8]),
                 v[9], v[10], v[11]};
  if (v.size() >= history_columns.size() + 2) {
    row.pore_pressure_ratio_max = v[history_columns.size()];
    row.high_pore_pressure_area = v[history_columns.size() + 1];
  }
  return row;
}

std::vector<std::string> columns_of(bool water) {
  std::vector<std::string> columns = history_columns;
  if (water) {
    columns.insert(columns.end(), pore_water_history_columns.begin(),
                   pore_water_history_columns.end());
  }
  return columns;
}

}  // namespace

FemHistory::FemHistory(std::filesystem::path path, bool water)
    : water_(water), csv_(std::move(path), columns_of(water)) {}

void FemHistory::resume(double time, const Logger& logger) {
  csv_.resume(time, logger);
  rows_.clear();
  for (const auto& values : csv_.rows()) rows_.push_back(row_of(values));
}

void FemHistory::add(const HistoryRow& row) {
  csv_.add(values_of(row, water_));
  rows_.push_back(row);
}

VtkSeries::VtkSeries(const std::filesystem::path& output_dir)
    : folder_(output_dir / "vtk"),
      mesh_series_(output_dir / "fem.pvd"),
      gauss_series_(output_dir / "fem_gauss_points.pvd") {}

void VtkSeries::resume(double time) {
  mesh_series_.resume(time);
  gauss_series_.resume(time);
}

namespace {

/// The element means of a frame's Gauss-point fields, and the points' own columns.
struct ElementMeans {
  std::vector<Vec4> stress, strain;
  std::vector<std::int32_t> material;
  std::vector<double> plastic, gauss_plastic;
  std::vector<std::int64_t> gauss_element;
  std::vector<Vec2> gauss_x;

  ElementMeans(const FemModel& model, const FemState& state, std::span<const Vec2> coordinates)
      : stress(static_cast<std::size_t>(model.element_count()), Vec4::Zero()),
        strain(stress.size(), Vec4::Zero()),
        material(stress.size()),
        plastic(stress.size(), 0.0),
        gauss_plastic(state.stress.size()),
        gauss_element(state.stress.size()),
        gauss_x(state.stress.size()) {
    const auto n_gauss = static_cast<std::size_t>(model.gauss_per_element());
    const auto n = static_cast<double>(n_gauss);
    for (std::size_t e = 0; e < stress.size(); ++e) {
      const ElementNodes x = model.mesh.element_nodes(static_cast<Index>(e), coordinates);
      for (std::size_t p = 0; p < n_gauss; ++p) {
        const std::size_t gp = e * n_gauss + p;
        stress[e] += state.stress[gp] / n;
        strain[e] += state.strain[gp] / n;
        plastic[e] += state.material_state[gp].plastic_shear_strain / n;
        gauss_plastic[gp] = state.material_state[gp].plastic_shear_strain;
        gauss_element[gp] = static_cast<std::int64_t>(e);
        gauss_x[gp] = map_to_physical(model.mesh.shape(), x, model.rule.local[p]);
      }
      material[e] = static_cast<std::int32_t>(model.mesh.material_id[e]);
    }
  }
};

/// A saturated model's frame fields (fem/pore_fluid.hpp): p and Δp at the nodes, r_u at
/// the Gauss points and as the element mean, p at the Gauss points.
struct PoreWaterFields {
  std::vector<double> excess, gauss_pressure, gauss_ratio, ratio;

  PoreWaterFields(const FemModel& model, const FemState& state)
      : excess(excess_pore_pressure(state)) {
    gauss_point_pressure(model, state.element_pore_pressure, gauss_pressure);
    pore_pressure_ratio(model, state, gauss_ratio);
    ratio = element_pore_pressure_ratio(model, gauss_ratio);
  }

  /// The fields point into this object and `state`: both must outlive the writing.
  void add_to(const FemState& state, std::vector<VtkField>& nodes, std::vector<VtkField>& elements,
              std::vector<VtkField>& gauss_points) const {
    nodes.push_back(vtk_field("pore_pressure", std::span<const double>(state.pore_pressure)));
    nodes.push_back(vtk_field("excess_pore_pressure", std::span<const double>(excess)));
    elements.push_back(vtk_field("pore_pressure_ratio", std::span<const double>(ratio)));
    gauss_points.push_back(vtk_field("pore_pressure", std::span<const double>(gauss_pressure)));
    gauss_points.push_back(vtk_field("pore_pressure_ratio", std::span<const double>(gauss_ratio)));
  }
};

}  // namespace

void VtkSeries::write(const FemModel& model, const FemState& state,
                      std::span<const Vec2> coordinates, const ElementQuality& quality) {
  const ElementMeans means(model, state, coordinates);
  const auto& [stress, strain, material, plastic, gauss_plastic, gauss_element, gauss_x] = means;
  const std::string stem = fmt::format("{:06d}", state.step);
  const auto mesh_file = folder_ / ("fem_" + stem + ".vtu");
  std::vector<VtkField> node_fields{
      vtk_field("displacement", std::span<const Vec2>(state.displacement)),
      vtk_field("velocity", std::span<const Vec2>(state.velocity))};
  std::vector<VtkField> element_fields{
      vtk_field("stress", std::span<const Vec4>(stress)),
      vtk_field("strain", std::span<const Vec4>(strain)),
      vtk_field("eps_q", std::span<const double>(quality.eps_q)),
      vtk_field("jacobian_ratio", std::span<const double>(quality.jacobian_ratio)),
      vtk_field("scaled_jacobian", std::span<const double>(quality.scaled_jacobian)),
      vtk_field("plastic_shear_strain", std::span<const double>(plastic)),
      vtk_field("material_id", std::span<const std::int32_t>(material)),
      vtk_field("yielded", std::span<const std::uint8_t>(quality.yielded))};
  std::vector<VtkField> gauss_fields{
      vtk_field("stress", std::span<const Vec4>(state.stress)),
      vtk_field("strain", std::span<const Vec4>(state.strain)),
      vtk_field("eps_q", std::span<const double>(quality.gauss_eps_q)),
      vtk_field("plastic_shear_strain", std::span<const double>(gauss_plastic)),
      vtk_field("yielded", std::span<const std::uint8_t>(state.yielded)),
      vtk_field("element", std::span<const std::int64_t>(gauss_element))};
  std::optional<PoreWaterFields> water;  // dry models' frames are as before
  if (model.fluid.active()) {
    water.emplace(model, state);
    water->add_to(state, node_fields, element_fields, gauss_fields);
  }
  write_vtk_mesh(mesh_file, state.time, coordinates, model.mesh.shape(), model.mesh.connectivity,
                 node_fields, element_fields);
  mesh_series_.add(state.time, std::filesystem::path("vtk") / mesh_file.filename());
  const auto gauss_file = folder_ / ("fem_gauss_points_" + stem + ".vtu");
  write_vtk_points(gauss_file, state.time, gauss_x, gauss_fields);
  gauss_series_.add(state.time, std::filesystem::path("vtk") / gauss_file.filename());
}

}  // namespace slide::fem
