#include "tools/interop/opensees_import.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "common/base/error.hpp"
#include "common/base/program.hpp"
#include "common/input/mesh_generation.hpp"
#include "common/io/opensees_reader.hpp"
#include "common/physics/constitutive.hpp"
#include "fem/element_kernels.hpp"
#include "fem/fem_model.hpp"
#include "fem/fem_output.hpp"
#include "fem/mesh_quality.hpp"
#include "fem/model_setup.hpp"
#include "fem/pore_fluid.hpp"

namespace slide::interop {
namespace {

/// Recorded stress/strain components per Gauss point: [xx, yy, xy] of a plane-strain
/// element or material; a multi-yield material's own "stress" (SSPquad passes the
/// request on to it) gives [xx, yy, zz, xy, stress ratio].
constexpr std::size_t components = 3;
constexpr std::size_t multi_yield_components = 5;

/// Gauss points OpenSees records per element of a class: FourNodeQuad's 2×2 rule, one
/// point for the others.
std::size_t recorded_points(std::string_view element_class) {
  return element_class == "FourNodeQuad" ? 4 : 1;
}

/// For each Gauss point of this project's rule, the index of the OpenSees point at the
/// same place. FourNodeQuad records its points counter-clockwise, (−,−), (+,−), (+,+),
/// (−,+), as quad4-2x2 orders them today; matching by place keeps the import right
/// whatever either order becomes.
std::vector<std::size_t> point_order(const fem::FemModel& model, std::string_view element_class) {
  const std::size_t n = recorded_points(element_class);
  std::vector<std::size_t> order(model.rule.local.size(), 0);
  if (n == 1) return order;
  constexpr std::array<std::array<double, 2>, 4> opensees_signs{
      {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}};
  for (std::size_t p = 0; p < order.size(); ++p) {
    const Vec2& xi = model.rule.local[p];
    for (std::size_t q = 0; q < n; ++q) {
      if (std::signbit(xi.x()) == (opensees_signs[q][0] < 0.0) &&
          std::signbit(xi.y()) == (opensees_signs[q][1] < 0.0)) {
        order[p] = q;
      }
    }
  }
  return order;
}

/// Reads rows at `time` and, when given, at the reference time.
struct Rows {
  RecorderRow at;
  std::optional<RecorderRow> reference;
};

class RecorderSet {
 public:
  RecorderSet(double time, std::optional<double> reference_time, const Logger* logger)
      : time_(time), reference_time_(reference_time), logger_(logger) {}

  Rows read(const std::filesystem::path& file, std::size_t columns, std::string_view layout,
            bool with_reference) const {
    Rows rows{read_recorder_row(file, time_, columns, layout), std::nullopt};
    note(file, rows.at);
    if (with_reference && reference_time_) {
      // The reference state comes first: the end of a gravity stage, before a later
      // step of the same time on the clock that loadConst -time 0.0 reset.
      rows.reference =
          read_recorder_row(file, *reference_time_, columns, layout, RepeatedTime::first);
      note(file, *rows.reference);
    }
    return rows;
  }

 private:
  void note(const std::filesystem::path& file, const RecorderRow& row) const {
    if (logger_ != nullptr) {
      logger_->info("  {}:{}: t = {} s, {} values", file.string(), row.line, row.time,
                    row.values.size());
    }
  }
  double time_;
  std::optional<double> reference_time_;
  const Logger* logger_;
};

/// Node vectors: two columns per recorded node (`-dof 1 2`), mapped to the mesh's nodes.
class NodeColumns {
 public:
  explicit NodeColumns(const OpenSeesMesh& model) {
    std::unordered_map<std::int64_t, std::size_t> position;
    for (std::size_t j = 0; j < model.all_node_tags.size(); ++j) {
      position.emplace(model.all_node_tags[j], j);
    }
    for (const std::int64_t tag : model.node_tags) column_.push_back(position.at(tag));
    recorded_ = model.all_node_tags.size();
  }
  std::size_t recorded() const { return recorded_; }
  std::vector<Vec2> vectors(const Rows& rows) const {
    std::vector<Vec2> v(column_.size(), Vec2::Zero());
    for (std::size_t n = 0; n < column_.size(); ++n) {
      const std::size_t j = 2 * column_[n];
      v[n] = Vec2(rows.at.values[j], rows.at.values[j + 1]);
      if (rows.reference) v[n] -= Vec2(rows.reference->values[j], rows.reference->values[j + 1]);
    }
    return v;
  }

 private:
  std::vector<std::size_t> column_;  ///< per mesh node: its position among the recorded nodes
  std::size_t recorded_ = 0;
};

std::string node_layout(std::size_t nodes) {
  return fmt::format(
      "-dof 1 2: 2 values for each of the model's {} nodes, in increasing tag "
      "order",
      nodes);
}

/// Pore pressures of the u–p nodes (ndf = 3): one column per such node of the model, in
/// increasing tag order (`-dof 3 vel`).
std::vector<double> pore_pressures(const OpenSeesMesh& model, const std::filesystem::path& file,
                                   const RecorderSet& recorders) {
  std::vector<double> p(model.node_tags.size(), 0.0);
  if (file.empty()) return p;
  std::vector<std::int64_t> up_tags;
  std::unordered_map<std::int64_t, std::size_t> mesh_node;
  for (std::size_t n = 0; n < model.node_tags.size(); ++n) {
    mesh_node.emplace(model.node_tags[n], n);
    if (model.node_dofs[n] == 3) up_tags.push_back(model.node_tags[n]);
  }
  if (up_tags.empty()) {
    throw Error(
        "{}: a pore-pressure recorder, but no node of the model has 3 degrees of freedom "
        "(u–p elements such as SSPquadUP)",
        file.string());
  }
  const Rows rows = recorders.read(
      file, up_tags.size(),
      fmt::format("-dof 3 vel: one value for each of the {} u–p nodes, in increasing tag order",
                  up_tags.size()),
      false);
  for (std::size_t j = 0; j < up_tags.size(); ++j) p[mesh_node.at(up_tags[j])] = rows.at.values[j];
  return p;
}

/// Gauss-point values of an element recorder, mapped to the rule's order: [xx, yy, 0, xy]
/// from `width` = 3 values per point, [xx, yy, zz, xy] from 5 (the fifth, the stress
/// ratio, is not kept); the reference row subtracted when there is one.
std::vector<Vec4> gauss_values(const Rows& rows, const std::vector<std::size_t>& order,
                               std::size_t recorded, std::size_t elements, std::size_t width) {
  const std::size_t n_gauss = order.size();
  const auto pick = [&](const std::vector<double>& v, std::size_t j) {
    return width == multi_yield_components ? Vec4(v[j], v[j + 1], v[j + 2], v[j + 3])
                                           : Vec4(v[j], v[j + 1], 0.0, v[j + 2]);
  };
  std::vector<Vec4> values(elements * n_gauss, Vec4::Zero());
  for (std::size_t e = 0; e < elements; ++e) {
    for (std::size_t p = 0; p < n_gauss; ++p) {
      const std::size_t j = (e * recorded + order[p]) * width;
      Vec4 value = pick(rows.at.values, j);
      if (rows.reference) value -= pick(rows.reference->values, j);
      values[e * n_gauss + p] = value;
    }
  }
  return values;
}

/// The values per point of a stress row: 3, or 5 for a multi-yield material's own stress.
std::size_t stress_width(const Rows& rows, const std::filesystem::path& file, std::size_t points,
                         std::string_view layout) {
  const std::size_t n = rows.at.values.size();
  if (n == points * components) return components;
  if (n == points * multi_yield_components) return multi_yield_components;
  throw Error(
      "{}:{}: the row at t = {} s has {} values after the time, expected {} ({}) or {} (5 "
      "per point: a multi-yield material's σxx σyy σzz σxy and stress ratio)",
      file.string(), rows.at.line, rows.at.time, n, points * components, layout,
      points * multi_yield_components);
}

/// What the elastic kernel makes of displacement `u` from the unstrained state: the
/// small-strain B·u at every Gauss point and, for one-point quads, the hourglass forces
/// K_q q. One elastic "step" of length 1 with velocity u, as fem-solve's geostatic stage
/// derives its state from its solution (fem/geostatic.cpp).
struct ElasticResponse {
  std::vector<Vec4> strain;  ///< [εxx, εyy, 0, γxy]
  std::vector<Vec2> hourglass_force;
};

ElasticResponse elastic_response(const fem::FemModel& model, const std::vector<Vec2>& u) {
  std::vector<ConstitutiveModel> elastic;
  for (const Material& material : model.materials) {
    elastic.push_back(ConstitutiveModel::elastic(material));
  }
  fem::FemState state = fem::make_rest_state(model);
  state.velocity = u;
  fem::update_stresses(model, model.reference, elastic, 1.0, false, state);
  return {std::move(state.strain), std::move(state.hourglass_force)};
}

const OpenSeesImportSpec& import_spec(const Case& c) {
  if (c.mesh.generator != MeshGenerator::opensees) {
    throw Error(
        "{}: mesh.generator is not \"opensees\": opensees2fem imports an OpenSees model "
        "(tools/interop/README.md)",
        c.file.string());
  }
  if (!c.opensees) {
    throw Error(
        "{}: no [opensees] table: name the recorder files to import (tools/interop/"
        "README.md)",
        c.file.string());
  }
  return *c.opensees;
}

/// The nodal recorders' displacement, velocity and acceleration (optional) into `state`.
void read_nodal_state(const OpenSeesImportSpec& spec, const RecorderSet& recorders,
                      const NodeColumns& nodes, fem::FemState& state) {
  const std::string layout = node_layout(nodes.recorded());
  state.displacement =
      nodes.vectors(recorders.read(spec.displacement, 2 * nodes.recorded(), layout, true));
  state.velocity =
      nodes.vectors(recorders.read(spec.velocity, 2 * nodes.recorded(), layout, false));
  if (!spec.acceleration.empty()) {
    state.acceleration =
        nodes.vectors(recorders.read(spec.acceleration, 2 * nodes.recorded(), layout, false));
  }
}

/// The element recorders' stresses (σzz of plane strain from the in-plane ones where they
/// lack it) and strains (else the elastic kernel's of the displacements) into `state`,
/// with the hourglass forces of that displacement.
void read_gauss_state(const OpenSeesImportSpec& spec, const RecorderSet& recorders,
                      const fem::FemModel& model, const std::string& element_class,
                      fem::FemState& state) {
  const std::size_t elements = static_cast<std::size_t>(model.element_count());
  const std::size_t recorded = recorded_points(element_class);
  const std::vector<std::size_t> order = point_order(model, element_class);
  const std::string element_layout = fmt::format(
      "{} values (xx, yy, xy) at each of the {} point(s) of each of the model's {} {} elements, in "
      "increasing tag order",
      components, recorded, elements, element_class);
  const Rows stress_rows = recorders.read(spec.stress, any_columns, element_layout, false);
  const std::size_t width =
      stress_width(stress_rows, spec.stress, elements * recorded, element_layout);
  state.stress = gauss_values(stress_rows, order, recorded, elements, width);
  if (width == components) {
    const auto n_gauss = order.size();
    for (std::size_t gp = 0; gp < state.stress.size(); ++gp) {
      const double nu = model.material_of(static_cast<Index>(gp / n_gauss)).poisson_ratio;
      state.stress[gp][2] = nu * (state.stress[gp][0] + state.stress[gp][1]);
    }
  }
  ElasticResponse response = elastic_response(model, state.displacement);
  state.strain = spec.strain.empty()
                     ? std::move(response.strain)
                     : gauss_values(recorders.read(spec.strain, elements * recorded * components,
                                                   element_layout, true),
                                    order, recorded, elements, components);
  state.hourglass_force = std::move(response.hourglass_force);
}

/// What the checkpoint records besides the state: PE_0 of the imported state, the
/// boundaries and the /solver record of the stage it is in, and where it came from.
fem::CheckpointContext import_context(const Case& c, const fem::FemModel& model,
                                      const fem::FemState& state, const std::string& element_class,
                                      double time) {
  const OpenSeesImportSpec& spec = *c.opensees;
  fem::CheckpointContext context;
  context.case_name = c.name;
  const std::vector<Vec2> no_velocity(static_cast<std::size_t>(model.node_count()), Vec2::Zero());
  context.pe0 =
      fem::compute_energies(model, model.reference, state, no_velocity, model.mesh.nodes).potential;
  const bool failure = c.fem.failure_stage && state.time > 0.0;
  context.boundary_conditions = fem::node_set_conditions(
      model.mesh, failure ? c.fem.failure_boundaries : c.fem.geostatic_boundaries);
  context.friction_coefficient = c.fem.friction_coefficient;
  context.solver["stage"] = std::string(failure ? "failure" : "geostatic");
  context.solver["source"] = std::string("opensees");
  context.solver["opensees_model"] = c.mesh.opensees_file.string();
  context.solver["opensees_element_class"] = element_class;
  context.solver["opensees_time"] = time;
  context.solver["opensees_start_time"] = spec.start_time;
  if (spec.reference_time) context.solver["opensees_reference_time"] = *spec.reference_time;
  context.solver["kinematics"] = std::string(to_string(model.kinematics));
  context.solver["element_type"] = std::string(to_string(model.mesh.element_type));
  context.solver["hourglass_coefficient"] = model.hourglass_coefficient;
  return context;
}

void log_import(const Logger* logger, const Case& c, const fem::FemModel& model,
                const OpenSeesMesh& tags, double time) {
  if (logger == nullptr) return;
  std::string ignored;
  for (const auto& [type, count] : tags.ignored)
    ignored += fmt::format(", {} {} ignored", count, type);
  logger->info("{}: {} nodes, {} {} elements → {}{}", c.mesh.opensees_file.string(),
               model.node_count(), model.element_count(), tags.element_class,
               to_string(model.mesh.element_type), ignored);
  logger->info("reading the recorders at t = {} s{}", time,
               c.opensees->reference_time
                   ? fmt::format(" (reference state at t = {} s)", *c.opensees->reference_time)
                   : std::string());
}

}  // namespace

FemCheckpoint import_opensees(const Case& c, double time, const Logger* logger) {
  const OpenSeesImportSpec& spec = import_spec(c);
  const double t0 = spec.start_time;
  if (time < t0) {
    throw Error("--time {} s is before opensees.start_time = {} s, the start of the failure stage",
                time, t0);
  }
  // The mesh as fem-solve builds it (validated, boundary names and grid checked), and the
  // tags that map the recorders' columns to it.
  Mesh mesh = build_mesh(c);
  const OpenSeesMesh model_tags = read_opensees_mesh(
      c.mesh.opensees_file, c.mesh.opensees_materials, c.mesh.ignore_elements, c.materials);
  const fem::FemModel model = fem::make_model(std::move(mesh), c.materials, c.fem.kinematics,
                                              c.fem.hourglass_coefficient, c.gravity, c.fem.water);
  log_import(logger, c, model, model_tags, time);

  const RecorderSet recorders(time, spec.reference_time, logger);
  fem::FemState state = fem::make_rest_state(model);
  state.time = time - t0;
  state.step = 0;
  read_nodal_state(spec, recorders, NodeColumns(model_tags), state);
  const std::vector<double> pore_pressure =
      pore_pressures(model_tags, spec.pore_pressure, recorders);
  read_gauss_state(spec, recorders, model, model_tags.element_class, state);

  FemCheckpoint checkpoint = fem::make_checkpoint(
      model, state, import_context(c, model, state, model_tags.element_class, time));
  checkpoint.header.producer = "opensees2fem (" + version_string() + ")";
  checkpoint.pore_pressure = pore_pressure;
  if (!spec.pore_pressure.empty() && model.fluid.active()) {
    // The u–p unknown of this project is the element's (fem/pore_fluid.hpp).
    checkpoint.element_pore_pressure = fem::element_pressure_from_nodes(model, pore_pressure);
  }
  return checkpoint;
}

}  // namespace slide::interop
