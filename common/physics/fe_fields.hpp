// The state of an FE model that evolves and that checkpoints carry: per node the
// displacement, velocity, acceleration and pore pressure, per element the hourglass forces
// of one-point quads and the pore pressure, per Gauss point the stress, strain and the
// material's state. fem-solve's FemState and the checkpoint module's FemCheckpoint both
// hold it, and fe_fields lists it once (common/physics/field_table.hpp): sizing a state,
// checking one read from a file and the checkpoint reader and writer walk the list.
#pragma once

#include <tuple>
#include <type_traits>
#include <vector>

#include "common/base/types.hpp"
#include "common/physics/constitutive.hpp"
#include "common/physics/field_table.hpp"

namespace slide {

struct FeFields {
  // Nodes. In the FE phase the velocity is the mid-step velocity v_{n+1/2} of the
  // leapfrog scheme and the acceleration (v_{n+1/2} − v_{n−1/2})/dt.
  std::vector<Vec2> displacement;     ///< u since t = 0, m
  std::vector<Vec2> velocity;         ///< m/s
  std::vector<Vec2> acceleration;     ///< m/s²
  std::vector<double> pore_pressure;  ///< Pa, compression positive (0 for dry analyses)
  /// Saturated models only: p of the state before shaking (the geostatic stage's
  /// hydrostatic field), the reference of the excess pore pressure Δp = p − p_static, Pa.
  std::vector<double> static_pore_pressure;

  // Elements: the hourglass generalised force Q = ∫ K_q dq of one-point quads, N (per m);
  // empty for the other element types.
  std::vector<Vec2> hourglass_force;
  /// Saturated models only: the pore pressure of each element (the u–p unknown; the
  /// nodal pore_pressure is derived from it, fem/pore_fluid.hpp), Pa.
  std::vector<double> element_pore_pressure;

  // Gauss points, element by element in the order of the element's rule.
  std::vector<Vec4> stress;  ///< [σxx, σyy, σzz, σxy], Pa, tension positive
  std::vector<Vec4> strain;  ///< total strain since t = 0, [εxx, εyy, εzz, γxy]
  std::vector<MaterialState> material_state;
  /// Saturated models only: σ′v0 = −σ′yy of the state before shaking (compression
  /// positive), the denominator of the pore-pressure ratio r_u = Δp/σ′v0, Pa.
  std::vector<double> initial_vertical_effective_stress;
  /// Saturated models only: p′₀ = −tr σ′/3 of the state before shaking, Pa.
  std::vector<double> initial_mean_effective_stress;
  /// Saturated models only: the largest r_u the point has reached since the state before
  /// shaking (the liquefaction rule of the transfer reads it, docs/method.md §10).
  std::vector<double> max_pore_pressure_ratio;
  /// Multi-yield surface stresses of the failure-stage models (none when no material
  /// uses the model in FE).
  SurfaceStresses surface_stress;
};

/// Every field of FeFields with its rows, dataset (under /nodes, /elements or
/// /gauss_points) and unit (common/io/checkpoint-schema.md).
inline constexpr std::tuple fe_fields{
    field(&FeFields::displacement, "displacement", "m", {.rows = RowKind::node}),
    field(&FeFields::velocity, "velocity", "m/s", {.rows = RowKind::node}),
    field(&FeFields::acceleration, "acceleration", "m/s^2", {.rows = RowKind::node}),
    field(&FeFields::pore_pressure, "pore_pressure", "Pa", {.rows = RowKind::node}),
    field(&FeFields::static_pore_pressure, "static_pore_pressure", "Pa",
          {.rows = RowKind::node, .presence = Presence::when_used}),
    field(&FeFields::hourglass_force, "hourglass_force", "N/m",
          {.rows = RowKind::element, .presence = Presence::when_used}),
    field(&FeFields::element_pore_pressure, "pore_pressure", "Pa",
          {.rows = RowKind::element, .presence = Presence::when_used}),
    field(&FeFields::stress, "stress", "Pa", {.rows = RowKind::gauss_point}),
    field(&FeFields::strain, "strain", "1", {.rows = RowKind::gauss_point}),
    field(&FeFields::material_state, "state", "", {.rows = RowKind::gauss_point}),
    field(&FeFields::initial_vertical_effective_stress, "initial_vertical_effective_stress", "Pa",
          {.rows = RowKind::gauss_point, .presence = Presence::when_used}),
    field(&FeFields::initial_mean_effective_stress, "initial_mean_effective_stress", "Pa",
          {.rows = RowKind::gauss_point, .presence = Presence::when_used}),
    field(&FeFields::max_pore_pressure_ratio, "max_pore_pressure_ratio", "1",
          {.rows = RowKind::gauss_point, .presence = Presence::when_used}),
    field(&FeFields::surface_stress, "state/surface_stress", "Pa", {.rows = RowKind::gauss_point}),
};
using FeFieldTable = std::remove_const_t<decltype(fe_fields)>;
static_assert(listed_bytes<FeFieldTable>() == sizeof(FeFields),
              "a member of FeFields is missing from fe_fields");

}  // namespace slide
